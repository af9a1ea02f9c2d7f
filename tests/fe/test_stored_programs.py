"""Compiled programs kept on disk: equal keys for equal content in every process, a
loaded program computes what the compiled one does, and a bad entry or folder is never
used."""

import json
import os
import subprocess
import sys
import textwrap
import warnings
from dataclasses import dataclass

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from bristlecrawler.fe import program_store, programs
from bristlecrawler.fe.programs import StoredProgram, Undigestible, digest, stored

# A program with a LAPACK kernel (as the banded solve and the modal analysis have): a
# process that only loads it must register the kernel before calling it.
PROGRAM = textwrap.dedent(
    """
    import sys
    import jax, jax.numpy as jnp, numpy as np
    from bristlecrawler.fe.programs import stored

    A = np.arange(16.0).reshape(4, 4) + 10.0 * np.eye(4)

    def make(scale):
        @jax.jit
        def solve(b, c):
            return {"x": jnp.linalg.solve(scale * A, b), "n": jnp.sum(b) * c}
        return stored(solve, "tests.solve", scale)

    f = make(2.0)
    out = f(jnp.arange(4.0), 3.0)
    print(repr(np.asarray(out["x"]).tolist()), float(out["n"]), len(f._loaded))
    """
)


def _run(folder, extra_env=None):
    env = dict(os.environ, BRISTLECRAWLER_JAX_CACHE=str(folder))
    env.pop("BRISTLECRAWLER_NO_JAX_CACHE", None)
    env.update(extra_env or {})
    done = subprocess.run(
        [sys.executable, "-c", PROGRAM], env=env, capture_output=True, text=True, timeout=120
    )
    assert done.returncode == 0, done.stderr
    return done.stdout.strip(), done.stderr


@dataclass(frozen=True)
class Spec:
    a: float
    b: tuple
    c: np.ndarray | None = None


leaves = st.one_of(
    st.none(),
    st.booleans(),
    st.integers(-(10**6), 10**6),
    st.floats(allow_nan=False),
    st.text(max_size=5),
)
trees = st.recursive(
    leaves,
    lambda inner: st.one_of(
        st.lists(inner, max_size=3).map(tuple),
        st.dictionaries(st.text(max_size=3), inner, max_size=3),
    ),
    max_leaves=12,
)


@given(trees, trees)
def test_digest_tells_content_apart(x, y):
    assert (digest(x) == digest(y)) == (repr(x) == repr(y))


def test_digest_sees_arrays_dataclasses_and_closures():
    a = np.arange(6.0)
    assert digest(Spec(1.0, (a,))) == digest(Spec(1.0, (a.copy(),)))
    assert digest(Spec(1.0, (a,))) != digest(Spec(1.0, (a + 1e-300,)))
    assert digest(a) != digest(a.astype(np.float32))
    assert digest(a) != digest(a.reshape(2, 3))

    def closure(k):
        return lambda x: x * k

    assert digest(closure(2.0)) == digest(closure(2.0))
    assert digest(closure(2.0)) != digest(closure(3.0))
    assert digest(jax.jit(closure(2.0))) != digest(jax.jit(closure(3.0)))
    with pytest.raises(Undigestible):
        digest(object())


def test_digest_is_the_same_in_another_process():
    code = (
        "import numpy as np; from bristlecrawler.fe.programs import digest; "
        "print(digest({'a': (1.5, 'x', None), 'b': np.arange(3.0)}))"
    )
    other = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert other.stdout.strip() == digest({"a": (1.5, "x", None), "b": np.arange(3.0)})


@pytest.mark.slow
def test_a_second_process_loads_the_program_and_gets_the_same_numbers(tmp_path):
    log = tmp_path / "programs.jsonl"
    first, _ = _run(tmp_path, {"BRISTLECRAWLER_PROGRAM_LOG": str(log)})
    entries = list((tmp_path / "programs").glob("*.bin"))
    assert len(entries) == 1
    stamp = entries[0].stat().st_mtime_ns
    second, _ = _run(tmp_path, {"BRISTLECRAWLER_PROGRAM_LOG": str(log)})
    assert second == first
    assert entries[0].stat().st_mtime_ns == stamp  # loaded, not written again
    lines = [json.loads(x) for x in log.read_text().splitlines()]
    assert [(x["program"], x["event"]) for x in lines] == [
        ("tests.solve", "compile"),
        ("tests.solve", "load"),
    ]
    assert lines[0]["entry"] == lines[1]["entry"] == entries[0].stem[:12]
    assert lines[0]["pid"] != lines[1]["pid"] and all(x["seconds"] >= 0 for x in lines)
    x = np.linalg.solve(2.0 * (np.arange(16.0).reshape(4, 4) + 10.0 * np.eye(4)), np.arange(4.0))
    assert first.startswith(repr(x.tolist()))


@pytest.mark.slow
def test_a_process_waits_for_another_compiling_the_same_program_then_loads_it(tmp_path):
    """While one process holds an entry's lock (compiling it), another that needs the same
    program waits instead of compiling it a second time; it compiles only once the lock
    is released without an entry (here), and loads where the entry was written."""
    _run(tmp_path / "first")
    (entry,) = (tmp_path / "first" / "programs").glob("*.bin")
    folder, log = tmp_path / "second", tmp_path / "log.jsonl"
    env = dict(os.environ, BRISTLECRAWLER_JAX_CACHE=str(folder))
    env["BRISTLECRAWLER_PROGRAM_LOG"] = str(log)
    env.pop("BRISTLECRAWLER_NO_JAX_CACHE", None)
    with programs.entry_lock(folder / "programs" / entry.name):
        child = subprocess.Popen(
            [sys.executable, "-c", PROGRAM], env=env, stdout=subprocess.PIPE, text=True
        )
        try:
            child.wait(timeout=10)
        except subprocess.TimeoutExpired:
            pass
        assert child.poll() is None and not log.exists()  # waiting, nothing compiled
    assert child.wait(timeout=120) == 0
    assert [json.loads(x)["event"] for x in log.read_text().splitlines()] == ["compile"]
    _run(folder, {"BRISTLECRAWLER_PROGRAM_LOG": str(log)})
    assert [json.loads(x)["event"] for x in log.read_text().splitlines()] == ["compile", "load"]


# The same kind of program with JAX's persistent cache on (as the CLI has it).
WITH_XLA_CACHE = textwrap.dedent(
    """
    import sys
    import jax, jax.numpy as jnp, numpy as np
    jax.config.update("jax_compilation_cache_dir", sys.argv[1])
    jax.config.update("jax_persistent_cache_min_compile_time_secs", 0.0)
    from bristlecrawler.fe.programs import stored

    def make(scale):
        @jax.jit
        def f(x, y):
            z = jnp.concatenate([x, y]) * scale
            w = jnp.concatenate([jnp.sin(z), z[::-1]])
            return jnp.cumsum(w) @ jnp.ones_like(w)
        return stored(f, "tests.concatenate", scale)

    print(float(make(2.0)(jnp.arange(8.0), jnp.arange(8.0) + 1.0)))
    """
)


@pytest.mark.slow
def test_a_program_in_jax_s_cache_is_stored_compiled_afresh(tmp_path):
    """A program that JAX's persistent cache already holds: the stored program is compiled
    again rather than taken from that cache (an executable read from it serialises
    without some of its kernels, and a process that loads it fails at its first call)."""
    env = dict(os.environ, BRISTLECRAWLER_JAX_CACHE=str(tmp_path / "stored"))
    env.pop("BRISTLECRAWLER_NO_JAX_CACHE", None)

    def run():
        cmd = [sys.executable, "-c", WITH_XLA_CACHE, str(tmp_path / "xla")]
        done = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=120)
        assert done.returncode == 0, done.stderr
        return done.stdout.strip()

    first = run()  # compiles: JAX's cache and the stored program written
    for entry in (tmp_path / "stored" / "programs").glob("*.bin"):
        entry.unlink()
    assert run() == first  # JAX's cache holds it; the stored program is written again
    assert run() == first  # loads the stored program and calls it


@pytest.mark.slow
@pytest.mark.parametrize("damage", ["truncate", "garbage", "flip"])
def test_a_damaged_entry_is_rebuilt_not_used(tmp_path, damage):
    first, _ = _run(tmp_path)
    (entry,) = (tmp_path / "programs").glob("*.bin")
    blob = entry.read_bytes()
    if damage == "truncate":
        entry.write_bytes(blob[: len(blob) // 2])
    elif damage == "garbage":
        entry.write_bytes(b"\0" * 100)
    else:  # a flipped bit the checksum must catch
        mid = len(blob) // 2
        entry.write_bytes(blob[:mid] + bytes([blob[mid] ^ 1]) + blob[mid + 1 :])
    again, _ = _run(tmp_path)
    assert again == first
    assert programs._read(entry) is not None  # rebuilt whole in place


def test_an_unwritable_folder_warns_once_and_the_program_runs(tmp_path, monkeypatch):
    blocker = tmp_path / "file"
    blocker.write_text("not a folder")
    monkeypatch.setattr(program_store, "_WARNED", set())
    f = StoredProgram(jax.jit(lambda x: 2.0 * x), "tests.double", "k", blocker / "programs")
    g = StoredProgram(jax.jit(lambda x: 3.0 * x), "tests.triple", "k", blocker / "programs")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        assert float(f(jnp.asarray(2.0))) == 4.0
        assert float(g(jnp.asarray(2.0))) == 6.0
    assert len(caught) == 1
    assert "not writable" in str(caught[0].message)


def test_another_environment_is_another_entry(tmp_path, monkeypatch):
    f = StoredProgram(jax.jit(lambda x: x + 1.0), "tests.inc", "k", tmp_path)
    sig = programs._signature((jnp.zeros(3),))
    before = f.path(sig)
    monkeypatch.setattr(programs, "environment", lambda: "another jaxlib")
    assert f.path(sig) != before


def test_traced_calls_run_the_jitted_function(tmp_path, monkeypatch):
    monkeypatch.setenv("BRISTLECRAWLER_JAX_CACHE", str(tmp_path))
    monkeypatch.delenv("BRISTLECRAWLER_NO_JAX_CACHE", raising=False)
    f = stored(jax.jit(lambda x, k: jnp.sin(x) * k), "tests.sin", 1)
    assert isinstance(f, StoredProgram)
    x = jnp.linspace(0.0, 1.0, 5)
    batched = jax.vmap(f, in_axes=(0, None))(x, 2.0)
    np.testing.assert_array_equal(batched, f(x, 2.0))
    np.testing.assert_allclose(jax.grad(lambda y: f(y, 2.0))(0.3), 2.0 * np.cos(0.3))
    assert not list(tmp_path.rglob("*.tmp"))


def test_the_opt_out_gives_the_jitted_function(monkeypatch):
    monkeypatch.setenv("BRISTLECRAWLER_NO_JAX_CACHE", "1")
    fn = jax.jit(lambda x: x)
    assert stored(fn, "tests.identity") is fn
