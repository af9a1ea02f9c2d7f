"""The stored programs' files as an attack surface: an entry that someone else could have
written is never unpickled, a file planted where an entry or a lock goes neither hangs the
run nor is written through, and the cache is private whatever the umask."""

import hashlib
import json
import os
import pickle
import stat
import threading
import warnings

import jax
import jax.numpy as jnp
import pytest

from bristlecrawler._files import open_lock
from bristlecrawler.fe import program_store, programs
from bristlecrawler.fe.programs import StoredProgram


@pytest.fixture(autouse=True)
def _own_key(tmp_path, monkeypatch):
    """A key of the test's own, and warnings said afresh."""
    monkeypatch.setenv("BRISTLECRAWLER_CACHE_KEY", str(tmp_path / "config" / "cache-key"))
    monkeypatch.delenv("BRISTLECRAWLER_PROGRAM_LOG", raising=False)
    monkeypatch.setattr(program_store, "_WARNED", set())


class _Unblocker:
    """Opens a FIFO for writing after a while, so that a reader stuck on it goes on (and
    the test fails rather than hangs); ``fired`` says whether it had to."""

    def __init__(self, fifo, mode=os.O_WRONLY):
        self.fired = False
        self._fifo, self._mode = fifo, mode
        self._timer = threading.Timer(10.0, self._open)
        self._timer.start()

    def _open(self):
        self.fired = True
        os.close(os.open(self._fifo, self._mode | os.O_NONBLOCK))

    def stop(self):
        self._timer.cancel()


def _program(folder, name="tests.scale", scale=2.0):
    return StoredProgram(jax.jit(lambda x: scale * x), name, f"key-{scale}", folder)


def _entry(f):
    return f.path(programs._signature((jnp.arange(3.0),)))


def _events(log):
    return [json.loads(x)["event"] for x in log.read_text().splitlines()] if log.exists() else []


def _call(f):
    return jnp.asarray(f(jnp.arange(3.0))).tolist()


class _Payload:
    """A pickle that makes a folder when loaded: what a planted entry would run."""

    def __init__(self, marker):
        self.marker = str(marker)

    def __reduce__(self):
        return (os.mkdir, (self.marker,))


@pytest.mark.parametrize("magic", [b"bristlecrawler-program-1\n", program_store.MAGIC])
def test_a_planted_entry_with_a_correct_checksum_is_not_unpickled(tmp_path, magic):
    folder = tmp_path / "cache" / "programs"
    f = _program(folder)
    entry, marker = _entry(f), tmp_path / "ran"
    folder.mkdir(parents=True)
    payload = pickle.dumps(_Payload(marker))
    entry.write_bytes(magic + hashlib.sha256(payload).digest() + payload)
    with pytest.warns(program_store.CacheWarning, match="not loaded"):
        assert _call(f) == [0.0, 2.0, 4.0]
    assert not marker.exists()
    assert programs._read(entry) is not None  # compiled, signed and stored in its place


def test_the_cache_is_private_whatever_the_umask(tmp_path):
    old = os.umask(0)
    try:
        f = _program(tmp_path / "cache" / "programs")
        assert _call(f) == [0.0, 2.0, 4.0]
    finally:
        os.umask(old)
    key = tmp_path / "config" / "cache-key"
    for p in (tmp_path / "cache", tmp_path / "cache" / "programs", key.parent):
        assert stat.S_IMODE(p.stat().st_mode) == 0o700, p
    for p in (_entry(f), key):
        assert stat.S_IMODE(p.stat().st_mode) == 0o600, p


def test_swapped_entries_are_compiled_again_not_run(tmp_path):
    folder = tmp_path / "programs"
    f, g = _program(folder, "tests.double", 2.0), _program(folder, "tests.triple", 3.0)
    assert _call(f) == [0.0, 2.0, 4.0] and _call(g) == [0.0, 3.0, 6.0]
    a, b = _entry(f), _entry(g)
    blob = a.read_bytes()
    a.write_bytes(b.read_bytes())
    b.write_bytes(blob)
    f.clear()
    g.clear()
    with pytest.warns(program_store.CacheWarning, match="signature does not match"):
        assert _call(f) == [0.0, 2.0, 4.0] and _call(g) == [0.0, 3.0, 6.0]


def _other_user(monkeypatch):
    uid = os.getuid()
    monkeypatch.setattr(os, "getuid", lambda: uid + 1)


@pytest.mark.parametrize("how", ["group-writable folder", "group-writable entry", "another user's"])
def test_an_entry_others_could_write_is_not_loaded(tmp_path, monkeypatch, how):
    folder, log = tmp_path / "cache" / "programs", tmp_path / "programs.jsonl"
    assert _call(_program(folder)) == [0.0, 2.0, 4.0]  # stored by the user
    f = _program(folder)
    entry = _entry(f)
    if how == "group-writable folder":
        folder.chmod(0o770)
    elif how == "group-writable entry":
        entry.chmod(0o620)
    else:
        _other_user(monkeypatch)
    monkeypatch.setenv("BRISTLECRAWLER_PROGRAM_LOG", str(log))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        assert _call(f) == [0.0, 2.0, 4.0]
    assert _events(log) == ["compile"]
    assert len([w for w in caught if w.category is program_store.CacheWarning]) == 1


@pytest.mark.parametrize("what", ["fifo", "device", "folder"])
def test_an_entry_that_is_not_a_regular_file_neither_hangs_nor_crashes(tmp_path, what):
    f = _program(tmp_path / "programs")
    entry = _entry(f)
    entry.parent.mkdir(parents=True)
    unblock = None
    if what == "fifo":
        os.mkfifo(entry)
        unblock = _Unblocker(entry)
    elif what == "device":
        entry.symlink_to("/dev/null")
    else:
        entry.mkdir()
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            assert _call(f) == [0.0, 2.0, 4.0]
    finally:
        if unblock is not None:
            unblock.stop()
    assert unblock is None or not unblock.fired
    said = [str(w.message) for w in caught if w.category is program_store.CacheWarning]
    assert "not loaded" in said[0]
    # A folder in the entry's place is not replaced either: a second warning says so.
    assert len(said) == (2 if what == "folder" else 1)


def test_a_lock_held_by_another_process_is_named_and_waited_for_a_bounded_time(
    tmp_path, monkeypatch, capfd
):
    f = _program(tmp_path / "programs")
    entry = _entry(f)
    entry.parent.mkdir(parents=True)
    fd = open_lock(entry.with_suffix(".lock"))
    os.write(fd, b"4242 node7\n")
    import fcntl

    fcntl.flock(fd, fcntl.LOCK_EX)  # another open file: as another process, it conflicts
    monkeypatch.setattr(program_store, "LOCK_WAIT_S", 0.5)
    try:
        assert _call(f) == [0.0, 2.0, 4.0]
    finally:
        os.close(fd)
    err = capfd.readouterr().err
    assert "process 4242 on node7 is compiling program tests.scale" in err and "waiting" in err
    assert "gave up waiting" in err


def test_a_link_where_a_lock_goes_is_not_written_through(tmp_path):
    f = _program(tmp_path / "programs")
    entry = _entry(f)
    entry.parent.mkdir(parents=True)
    victim = tmp_path / "victim"
    entry.with_suffix(".lock").symlink_to(victim)  # to nothing: opening it would create it
    with pytest.warns(program_store.CacheWarning, match="is a link"):
        assert _call(f) == [0.0, 2.0, 4.0]
    assert not victim.exists() and entry.with_suffix(".lock").is_symlink()


def test_a_fifo_as_the_program_log_does_not_hang(tmp_path, monkeypatch):
    log = tmp_path / "log"
    os.mkfifo(log)
    monkeypatch.setenv("BRISTLECRAWLER_PROGRAM_LOG", str(log))
    unblock = _Unblocker(log, os.O_RDONLY)
    try:
        with pytest.warns(program_store.CacheWarning, match="program log"):
            assert _call(_program(tmp_path / "programs")) == [0.0, 2.0, 4.0]
    finally:
        unblock.stop()
    assert not unblock.fired


def test_a_key_others_can_read_turns_the_store_off_with_one_warning(tmp_path):
    key = tmp_path / "config" / "cache-key"
    key.parent.mkdir()
    key.write_text("k" * 64)
    key.chmod(0o644)
    f = _program(tmp_path / "programs")
    with pytest.warns(program_store.CacheWarning, match="read by group or others"):
        assert _call(f) == [0.0, 2.0, 4.0]
    assert not _entry(f).exists() and key.read_text() == "k" * 64


def test_jax_s_cache_is_made_private_and_not_used_in_a_folder_others_can_write(
    tmp_path, monkeypatch
):
    """JAX's entries are executables too: its folder is made 0700 whatever the umask, and
    one that group or others may write is not used (one warning)."""
    from bristlecrawler.fe.cache import enable_compilation_cache

    monkeypatch.delenv("BRISTLECRAWLER_NO_JAX_CACHE", raising=False)
    monkeypatch.delenv("BRISTLECRAWLER_XLA_CACHE", raising=False)
    before = jax.config.jax_compilation_cache_dir
    try:
        old = os.umask(0)
        try:
            made = enable_compilation_cache(tmp_path / "mine" / "jax")
        finally:
            os.umask(old)
        assert made == tmp_path / "mine" / "jax"
        assert stat.S_IMODE(made.stat().st_mode) == 0o700
        shared = tmp_path / "shared"
        shared.mkdir()
        shared.chmod(0o777)
        with pytest.warns(program_store.CacheWarning, match="written by group or others"):
            assert enable_compilation_cache(shared) is None
    finally:
        jax.config.update("jax_compilation_cache_dir", before)
