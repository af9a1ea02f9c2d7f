"""Compiled FE programs kept on disk, so that a second process skips tracing and compiling.

JAX's persistent cache keeps only XLA's output: a new process still traces and lowers every
program (about 9 s for the paper crawler's step on an idle 2-core machine, over a minute
under load) before it can look the executable up. A :class:`StoredProgram` wraps a jitted
function made by a factory (``make_step(topo, terms, integrator)``, ...) and keys its
compiled executables by

* a digest of the factory's name and arguments (everything the program closes over; see
  :func:`digest`),
* the argument types of the call (tree structure, shapes, dtypes, weak types),
* a digest of the package's own source files, the jax and jaxlib versions, the device
  kind and the XLA flags,

so that a process that calls a factory with equal arguments loads the executable and runs it
at once. An entry that cannot be read or loaded (truncated, corrupt, written by another
jaxlib) is ignored and rebuilt; a cache folder that cannot be written gives one warning and
the run goes on, compiling as JAX would.

The store lives in ``programs/`` of the compilation cache folder
(:func:`bristlecrawler.fe.cache.cache_folder`); ``BRISTLECRAWLER_NO_JAX_CACHE=1`` turns it
off with the rest of the cache.
"""

from __future__ import annotations

import dataclasses
import enum
import functools
import hashlib
import json
import os
import stat
import sys
import threading
import time
import types
import weakref
from pathlib import Path
from typing import Any

import jax
import numpy as np

from bristlecrawler._files import UnfitFile, kind
from bristlecrawler.fe.cache import cache_folder
from bristlecrawler.fe.program_store import (
    LOAD_LOCK,
    CacheWarning,
    entry_lock,
    read_entry,
    warn_once,
    write_entry,
)

__all__ = ["CacheWarning", "StoredProgram", "Undigestible", "digest", "stored"]

_LIVE: weakref.WeakSet = weakref.WeakSet()


class Undigestible(TypeError):
    """An object whose content cannot be hashed stably across processes."""


def digest(*objs: Any) -> str:
    """A hex digest of ``objs`` that is equal in every process for equal content.

    Takes numbers, strings, bytes, None, enums, tuples, lists, dicts, sets of these, numpy
    and JAX arrays (dtype, shape and bytes), dataclasses and plain objects (class and
    fields), and functions (module, name, bytecode, constants, defaults and the values they
    close over). Raises :class:`Undigestible` for anything else (then the program is not
    stored: an unknown object might change the program without changing the key)."""
    h = hashlib.sha256()
    for obj in objs:
        _feed(h, obj, 0)
    return h.hexdigest()


def _feed(h, obj: Any, depth: int) -> None:
    if depth > 64:
        raise Undigestible("nesting deeper than 64")
    put = h.update
    if obj is None or isinstance(obj, bool | int | float | complex | str | bytes):
        put(f"{type(obj).__name__}:{obj!r};".encode())
    elif isinstance(obj, enum.Enum):
        put(f"enum:{type(obj).__module__}.{type(obj).__qualname__}.{obj.name};".encode())
    elif isinstance(obj, np.ndarray | np.generic | jax.Array):
        a = np.asarray(obj)
        if a.dtype == object:
            raise Undigestible("object array")
        put(f"array:{a.dtype.str}:{a.shape};".encode())
        put(np.ascontiguousarray(a).tobytes())
    elif isinstance(obj, tuple | list):
        put(f"{type(obj).__name__}[{len(obj)}](".encode())
        for x in obj:
            _feed(h, x, depth + 1)
        put(b")")
    elif isinstance(obj, dict):
        put(f"dict[{len(obj)}](".encode())
        for k in sorted(obj, key=repr):
            _feed(h, k, depth + 1)
            _feed(h, obj[k], depth + 1)
        put(b")")
    elif isinstance(obj, frozenset | set):
        put(b"set(" + "".join(sorted(digest(x) for x in obj)).encode() + b")")
    elif isinstance(obj, functools.partial):
        put(b"partial(")
        _feed(h, (obj.func, obj.args, obj.keywords), depth + 1)
        put(b")")
    elif isinstance(obj, types.FunctionType):
        _feed_function(h, obj, depth)
    elif isinstance(obj, types.MethodType):
        put(b"method(")
        _feed(h, (obj.__func__, obj.__self__), depth + 1)
        put(b")")
    elif isinstance(obj, StoredProgram):
        put(f"stored:{obj.name}:{obj.key};".encode())
    elif isinstance(obj, type):
        put(f"type:{obj.__module__}.{obj.__qualname__};".encode())
    elif hasattr(obj, "__wrapped__") and callable(obj):  # jax.jit and functools.wraps
        put(b"wrapped(")
        _feed(h, obj.__wrapped__, depth + 1)
        put(b")")
    elif dataclasses.is_dataclass(obj):
        cls = type(obj)
        put(f"dc:{cls.__module__}.{cls.__qualname__}(".encode())
        for f in dataclasses.fields(obj):
            put(f.name.encode())
            _feed(h, getattr(obj, f.name), depth + 1)
        put(b")")
    elif hasattr(obj, "__dict__") and type(obj).__module__.startswith("bristlecrawler"):
        cls = type(obj)
        put(f"obj:{cls.__module__}.{cls.__qualname__}(".encode())
        _feed(h, vars(obj), depth + 1)
        put(b")")
    else:
        raise Undigestible(f"cannot digest a {type(obj).__module__}.{type(obj).__qualname__}")


def _feed_function(h, fn: types.FunctionType, depth: int) -> None:
    code = fn.__code__
    h.update(f"fn:{fn.__module__}.{fn.__qualname__}:".encode())
    _feed_code(h, code, depth)
    _feed(h, (fn.__defaults__, fn.__kwdefaults__), depth + 1)
    cells = fn.__closure__ or ()
    _feed(h, tuple(c.cell_contents for c in cells), depth + 1)


def _feed_code(h, code: types.CodeType, depth: int) -> None:
    h.update(code.co_code)
    h.update(repr(code.co_names).encode())
    for c in code.co_consts:
        if isinstance(c, types.CodeType):
            _feed_code(h, c, depth + 1)
        else:
            _feed(h, c, depth + 1)


@functools.lru_cache(maxsize=1)
def environment() -> str:
    """A digest of what makes a compiled program valid beyond its own inputs: the
    package's source files, jax and jaxlib versions, float64, the device and XLA flags."""
    import jaxlib

    root = Path(__file__).resolve().parents[1]
    h = hashlib.sha256()
    for path in sorted(root.rglob("*.py")):
        h.update(str(path.relative_to(root)).encode())
        h.update(path.read_bytes())
    dev = jax.devices()[0]
    h.update(
        repr(
            (
                jax.__version__,
                jaxlib.__version__,
                sys.version_info[:2],
                bool(jax.config.jax_enable_x64),
                dev.platform,
                getattr(dev, "device_kind", ""),
                os.environ.get("XLA_FLAGS", ""),
            )
        ).encode()
    )
    return h.hexdigest()


def _signature(args: tuple) -> tuple | None:
    """The argument types of a call, or None if an argument is traced (the program is
    then called inside another transformation and runs as the jitted function)."""
    leaves, tree = jax.tree.flatten(args)
    sig = []
    for x in leaves:
        if isinstance(x, jax.core.Tracer):
            return None
        if isinstance(x, jax.Array | np.ndarray | np.generic):
            sig.append((x.shape, x.dtype.str, bool(getattr(x, "weak_type", False))))
        elif isinstance(x, bool | int | float | complex):
            sig.append(type(x).__name__)
        else:
            return None
    return tree, tuple(sig)


class StoredProgram:
    """A jitted function whose executables are kept in memory and on disk.

    ``fn`` is the jitted function, ``name`` the factory's dotted name and ``key`` the
    digest of the factory's arguments. Called with concrete arguments it runs the stored
    executable for their types (loading it, or compiling and storing it, the first time);
    called with traced arguments (inside ``jit``, ``vmap``, ``grad``) it is ``fn``."""

    def __init__(self, fn, name: str, key: str, folder: Path):
        self.fn, self.name, self.key, self.folder = fn, name, key, folder
        self._loaded: dict = {}
        self._lock = threading.Lock()
        functools.update_wrapper(self, fn)
        _LIVE.add(self)

    def lower(self, *args, **kwargs):
        return self.fn.lower(*args, **kwargs)

    def __call__(self, *args):
        sig = _signature(args)
        if sig is None:
            return self.fn(*args)
        exe = self._loaded.get(sig)
        if exe is None:
            with self._lock:
                exe = self._loaded.get(sig)
                if exe is None:
                    exe = self._loaded[sig] = self._load_or_compile(sig, args)
        return exe(*args)

    def clear(self) -> None:
        """Forget the executables held in memory (the disk keeps them)."""
        self._loaded.clear()

    def path(self, sig) -> Path:
        """The entry's file for the argument types ``sig``."""
        name = hashlib.sha256(f"{self.key}{environment()}{sig!r}".encode()).hexdigest()
        return self.folder / f"{name[:40]}.bin"

    def _load_or_compile(self, sig, args):
        path = self.path(sig)
        start = time.perf_counter()
        exe = _read(path)
        if exe is None:
            # Processes that need the same program (the workers of a sweep, the test
            # processes) compile it once: the others wait for the entry and load it.
            with entry_lock(path, self.name):
                exe = _read(path)
                if exe is None:
                    return self._compile(path, args, start)
        _log(self, path, "load", start)
        _COUNTS["loaded"] += 1
        return exe

    def _compile(self, path: Path, args, start: float):
        # Where JAX's cache is on and cannot be bypassed, its executable would not load in
        # another process: compile and store nothing.
        fresh = _bypass_jax_cache() or not jax.config.jax_compilation_cache_dir
        _FRESH.on = fresh
        try:
            exe = self.fn.lower(*args).compile()
        finally:
            _FRESH.on = False
        _log(self, path, "compile", start)
        _COUNTS["compiled"] += 1
        if fresh:
            _write(path, exe, self.name)
        return exe


def _log(program: StoredProgram, path: Path, event: str, start: float) -> None:
    """One JSON line per load or compile in the file ``BRISTLECRAWLER_PROGRAM_LOG`` names
    (unset: nothing): which program, which entry, how long, in which process. It tells
    where a cold start's time goes and which structures a set of runs compiled. Under
    pytest the line also names the test that asked for the program."""
    target = os.environ.get("BRISTLECRAWLER_PROGRAM_LOG")
    if not target:
        return
    line = {
        "program": program.name,
        "entry": path.stem[:12],
        "event": event,
        "seconds": round(time.perf_counter() - start, 3),
        "pid": os.getpid(),
        "time": time.time(),
    }
    if "PYTEST_CURRENT_TEST" in os.environ:
        line["test"] = os.environ["PYTEST_CURRENT_TEST"].rsplit(" (", 1)[0]
    try:
        _append(target, json.dumps(line) + "\n")
    except OSError as exc:
        warn_once("log", f"program log {target} not written: {exc.strerror or exc}")


def _append(target: str, text: str) -> None:
    """Append ``text`` to the regular file ``target`` in one write (appends do not
    interleave), never through a link, nor into a FIFO or a device (which would hang)."""
    flags = os.O_WRONLY | os.O_APPEND | os.O_CREAT | os.O_NONBLOCK
    fd = os.open(target, flags | getattr(os, "O_NOFOLLOW", 0), 0o600)
    try:
        mode = os.fstat(fd).st_mode
        if not stat.S_ISREG(mode):
            raise UnfitFile(f"it is {kind(mode)}")
        os.write(fd, text.encode())
    finally:
        os.close(fd)


#: Set in a thread while it compiles a program to store.
_FRESH = threading.local()


@functools.lru_cache(maxsize=1)
def _bypass_jax_cache() -> bool:
    """Make JAX's persistent cache miss for the programs this module compiles to store
    (in the thread that compiles them; every other compilation uses it as before).
    Returns False where JAX's private hook is not there.

    An executable that JAX read from its persistent cache serialises without the object
    code of some of its kernels: a later process that loads it fails at the first call
    ("Function concatenate.2_kernel not found"). A stored program is therefore always
    compiled afresh (and JAX's cache written as usual)."""
    try:
        from jax._src import compiler

        original = compiler._cache_read
    except (ImportError, AttributeError):
        return False

    def read(*args, **kwargs):
        if getattr(_FRESH, "on", False):
            return None, None
        return original(*args, **kwargs)

    compiler._cache_read = read
    return True


@functools.lru_cache(maxsize=1)
def _register_custom_calls() -> None:
    """Register the LAPACK kernels that the FE programs call (the banded solve, the modal
    analysis). JAX registers them when it lowers a program that uses them; a process that
    only loads programs must do it itself, or the first call of a loaded program jumps to
    an unregistered kernel (a segmentation fault)."""
    try:
        from jax._src.lax.linalg import initialize_lapack

        initialize_lapack()
    except Exception:  # the private hook moved: lowering a solve registers them
        import jax.numpy as jnp

        jax.jit(jnp.linalg.solve).lower(jnp.eye(2), jnp.ones(2))


def _read(path: Path):
    """The executable stored at ``path``, or None if absent or refused (see
    :mod:`bristlecrawler.fe.program_store`)."""
    from jax.experimental import serialize_executable

    _register_custom_calls()
    return read_entry(path, serialize_executable.deserialize_and_load)


def _write(path: Path, exe, name: str) -> None:
    """Store ``exe`` at ``path`` (signed, atomically)."""
    from jax.experimental import serialize_executable

    try:
        with LOAD_LOCK:
            serialized = serialize_executable.serialize(exe)
    except Exception as exc:
        warn_once("serialize", f"compiled program {name} not stored: {exc}")
        return
    write_entry(path, serialized, name)


def stored(fn, name: str, *static: Any):
    """``fn`` (jitted) as a :class:`StoredProgram` keyed by ``name`` and ``static`` (the
    factory's arguments); ``fn`` itself when the cache is off or ``static`` cannot be
    digested."""
    folder = cache_folder()
    if folder is None:
        return fn
    try:
        key = digest(name, static)
    except Undigestible:
        return fn
    return StoredProgram(fn, name, key, folder / "programs")


#: Programs this process compiled, and loaded from the store, so far.
_COUNTS = {"compiled": 0, "loaded": 0}


def counts() -> dict[str, int]:
    """How many programs this process has compiled and loaded from the store: what a
    caller that timed the preparation of its programs compares before and after, to say
    which of the two it was."""
    return dict(_COUNTS)


def clear_loaded() -> None:
    """Forget every stored program's executables held in memory (as ``jax.clear_caches``
    does for jitted functions); the disk keeps them."""
    for p in list(_LIVE):
        p.clear()
