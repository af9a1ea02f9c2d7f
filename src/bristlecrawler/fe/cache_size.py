"""The compilation caches' size: at most ``BRISTLECRAWLER_CACHE_MB`` MB together.

An entry's last use is its access or modification time, whichever is later (a stored
program's access time is set when it is loaded); the least recently used are removed
first, when a program is stored and when JAX's cache is enabled (JAX's cache has no limit
of its own without the ``filelock`` package). Only the caches' entries are ever removed: links and
files of other names in the folder are left as they are, and a folder that is not the
user's alone is not touched.
"""

from __future__ import annotations

import contextlib
import os
from pathlib import Path

from bristlecrawler._files import CACHE_LIMIT_MB, cache_limit_bytes, untrusted_folder

_PROGRAMS = "programs"


def _entries(folder: Path) -> list[tuple[float, int, Path]]:
    """``(last use, bytes, path)`` of every entry of both caches in ``folder``: stored
    programs (``programs/*.bin``) and JAX's (``*-cache``); links and other files are not
    entries, and are never removed."""
    found = []
    for where, suffix in ((folder / _PROGRAMS, ".bin"), (folder, "-cache")):
        try:
            listing = list(os.scandir(where))
        except OSError:
            continue
        for e in listing:
            try:
                if e.name.endswith(suffix) and e.is_file(follow_symlinks=False):
                    st = e.stat(follow_symlinks=False)
                    found.append((max(st.st_atime, st.st_mtime), st.st_size, Path(e.path)))
            except OSError:
                continue  # removed meanwhile by another process
    return found


def cache_usage(folder: Path) -> dict[str, tuple[int, int]]:
    """``{"programs": (entries, bytes), "jax": (entries, bytes)}`` of ``folder``."""
    usage = {"programs": [0, 0], "jax": [0, 0]}
    for _, size, path in _entries(folder):
        kind = "programs" if path.suffix == ".bin" else "jax"
        usage[kind][0] += 1
        usage[kind][1] += size
    return {k: (n, b) for k, (n, b) in usage.items()}


def _remove(path: Path) -> None:
    """Remove an entry, with JAX's access-time file, or the stored program's lock file
    where no process holds it (one that does is compiling the program again)."""
    with contextlib.suppress(OSError):
        path.unlink()
    if path.suffix == ".bin":
        _remove_unheld(path.with_suffix(".lock"))
    else:
        with contextlib.suppress(OSError):
            path.with_name(path.name.removesuffix("-cache") + "-atime").unlink()


def _remove_unheld(lock: Path) -> None:
    try:
        import fcntl

        fd = os.open(lock, os.O_RDWR | getattr(os, "O_NOFOLLOW", 0) | os.O_NONBLOCK)
    except (ImportError, OSError):
        return
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        lock.unlink()
    except OSError:
        pass
    finally:
        os.close(fd)


def evict(folder: Path, limit: int | None = None, keep: Path | None = None) -> int:
    """Remove the least recently used entries of ``folder``'s caches until they hold at
    most ``limit`` bytes [default: :func:`cache_limit_bytes`], ``keep`` (the entry just
    written) last of all; returns the bytes removed. A folder that is not the user's
    alone is left as it is."""
    if untrusted_folder(folder) is not None:
        return 0
    if limit is None:
        try:
            limit = cache_limit_bytes()
        except ValueError:  # the CLI refuses it; a library caller keeps the default
            limit = CACHE_LIMIT_MB << 20
    entries = sorted(_entries(folder), key=lambda e: (e[2] == keep, e[0]))
    total, removed = sum(size for _, size, _ in entries), 0
    for _, size, path in entries:
        if total - removed <= limit:
            break
        _remove(path)
        removed += size
    return removed


def clear(folder: Path) -> int:
    """Remove every entry of ``folder``'s caches (the folders and the key stay); returns
    the bytes removed."""
    if untrusted_folder(folder) is not None:
        return 0
    entries = _entries(folder)
    for _, _, path in entries:
        _remove(path)
    return sum(size for _, size, _ in entries)
