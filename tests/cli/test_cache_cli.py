"""The compilation caches' size limit, and ``bristlecrawler cache``: the least recently
used entries go first, only the caches' own entries are ever removed, and a limit that is
not a size is refused as an option would be."""

import json
import os
import time

import pytest

from bristlecrawler.fe import program_store
from bristlecrawler.fe.cache_size import cache_usage, evict

MB = 1 << 20


@pytest.fixture
def cache(tmp_path, monkeypatch):
    """An empty cache folder of the test's own, with its own key."""
    folder = tmp_path / "cache"
    (folder / "programs").mkdir(parents=True, mode=0o700)
    folder.chmod(0o700)
    monkeypatch.setenv("BRISTLECRAWLER_JAX_CACHE", str(folder))
    monkeypatch.delenv("BRISTLECRAWLER_NO_JAX_CACHE", raising=False)
    monkeypatch.setenv("BRISTLECRAWLER_CACHE_KEY", str(tmp_path / "key"))
    monkeypatch.setattr(program_store, "_WARNED", set())
    return folder


def _file(path, mb, age_s):
    path.write_bytes(b"\0" * int(mb * MB))
    then = time.time() - age_s
    os.utime(path, (then, then))
    return path


def test_the_least_recently_used_entries_go_first_and_nothing_else(cache, monkeypatch):
    old = _file(cache / "programs" / "old.bin", 1, 300)
    used = _file(cache / "programs" / "used.bin", 1, 200)
    jax_old = _file(cache / "jit_f-abc-cache", 1, 250)
    _file(cache / "jit_f-abc-atime", 0, 250)
    new = _file(cache / "programs" / "new.bin", 1, 10)
    other = _file(cache / "notes.txt", 1, 1000)  # not an entry: never removed
    (cache / "programs" / "link.bin").symlink_to(other)
    monkeypatch.setenv("BRISTLECRAWLER_CACHE_MB", "2")
    assert cache_usage(cache) == {"programs": (3, 3 * MB), "jax": (1, MB)}
    assert evict(cache) == 2 * MB
    assert not old.exists() and not jax_old.exists() and not (cache / "jit_f-abc-atime").exists()
    assert used.exists() and new.exists() and other.exists()
    assert (cache / "programs" / "link.bin").is_symlink()


def test_a_loaded_program_counts_as_used_and_a_stored_one_evicts_the_oldest(cache, monkeypatch):
    monkeypatch.setenv("BRISTLECRAWLER_CACHE_MB", "2")
    first, second = cache / "programs" / "first.bin", cache / "programs" / "second.bin"
    program_store.write_entry(first, (b"1" * (MB * 9 // 10), None, None), "first")
    program_store.write_entry(second, (b"2" * (MB * 9 // 10), None, None), "second")
    then = time.time() - 100
    os.utime(first, (then - 50, then - 50))
    os.utime(second, (then, then))
    assert program_store.read_entry(first, lambda *a: "loaded") == "loaded"  # used now
    program_store.write_entry(
        cache / "programs" / "third.bin", (b"3" * (MB * 9 // 10), None, None), "third"
    )
    assert sorted(p.name for p in (cache / "programs").glob("*.bin")) == ["first.bin", "third.bin"]


def test_cache_info_and_clear(cache, run_cli):
    _file(cache / "programs" / "a.bin", 1, 0)
    _file(cache / "jit_g-1-cache", 0.5, 0)
    _file(cache / "README", 0.1, 0)
    code, out, err = run_cli(["cache", "info", "--json"])
    assert code == 0, err
    info = json.loads(out)
    assert info["compilation_cache"] == str(cache)
    assert info["stored_programs"] == {"entries": 1, "bytes": MB}
    assert info["jax_programs"] == {"entries": 1, "bytes": MB // 2}
    assert info["limit_bytes"] == 2048 * MB
    code, out, _ = run_cli(["cache", "info"])
    assert "1.5 MB of at most 2048.0 MB (BRISTLECRAWLER_CACHE_MB)" in out
    code, out, _ = run_cli(["cache", "clear"])
    assert code == 0 and out.startswith("removed 2 compiled programs (1.5 MB)")
    assert sorted(p.name for p in cache.rglob("*")) == ["README", "programs"]


@pytest.mark.parametrize("value", ["lots", "-5", "0", "1.5"])
def test_a_limit_that_is_not_a_size_is_refused_before_any_command(
    cache, run_cli, value, monkeypatch
):
    monkeypatch.setenv("BRISTLECRAWLER_CACHE_MB", value)
    code, out, err = run_cli(["reduced", "--cycles", "1", "--out", str(cache.parent / "run")])
    assert (code, out, err.count("\n")) == (2, "", 1)
    assert err.startswith("error: BRISTLECRAWLER_CACHE_MB=") and "whole number of MB" in err
    assert not (cache.parent / "run").exists()
