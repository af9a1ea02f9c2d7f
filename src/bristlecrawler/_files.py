"""Files opened so that what is at a path cannot hang, crash or redirect the tool.

Reading: a path is opened without blocking (a FIFO with no writer would wait forever),
checked to be a regular file (not a FIFO, a device or a folder) of a size that fits, and
only then read. Writing: a file the tool creates is opened with ``O_NOFOLLOW`` (a link
planted where it goes is refused, and nothing it points at changes) and ``O_EXCL`` where
it must be new. Caches: folders are created ``0700`` and entries ``0600`` whatever the
umask, and a folder or entry that another user owns, or that group or others may write,
is not trusted (as OpenSSH treats its keys).
"""

from __future__ import annotations

import contextlib
import os
import stat
import threading
from pathlib import Path

_NOFOLLOW = getattr(os, "O_NOFOLLOW", 0)
_NONBLOCK = getattr(os, "O_NONBLOCK", 0)
_NOCTTY = getattr(os, "O_NOCTTY", 0)
#: The largest input file read (a scenario, a study, a history, a texture law, a
#: recording): larger ones are refused before reading rather than filling the memory.
MAX_INPUT_BYTES = 1 << 30
#: ... of a small structured file (TOML, JSON), which is a few kB when honest.
MAX_SMALL_BYTES = 16 << 20


class UnfitFile(OSError):
    """What is at a path cannot be read (or written) as the file it should be; the
    message says why in a few words."""


def xdg_home(variable: str, fallback: str) -> Path:
    """The base folder ``$variable`` names (``XDG_CACHE_HOME``, ``XDG_CONFIG_HOME``), or
    ``~/fallback``: as the XDG base directory rules say, a value that is empty or not an
    absolute path is ignored (a relative one would put the tool's files wherever it runs)."""
    given = os.environ.get(variable, "")
    if given and os.path.isabs(given):
        return Path(given)
    return Path.home() / fallback


#: What the compilation caches (stored programs and JAX's) may hold together, in MB,
#: unless ``BRISTLECRAWLER_CACHE_MB`` says otherwise: a structure's programs take tens of
#: MB, so this holds those of dozens of structures.
CACHE_LIMIT_MB = 2048


def cache_limit_bytes() -> int:
    """The compilation caches' size limit in bytes: ``$BRISTLECRAWLER_CACHE_MB`` MB, else
    :data:`CACHE_LIMIT_MB`. ValueError, saying what the variable takes, for a value that
    is not a whole number of MB >= 1."""
    given = os.environ.get("BRISTLECRAWLER_CACHE_MB", "").strip()
    if not given:
        return CACHE_LIMIT_MB << 20
    try:
        mb = int(given)
    except ValueError:
        mb = 0
    if not 1 <= mb <= 1 << 30:
        raise ValueError(
            f"BRISTLECRAWLER_CACHE_MB={given[:40]!r} is not a size: give a whole number of "
            f"MB >= 1 (default {CACHE_LIMIT_MB}), or BRISTLECRAWLER_NO_JAX_CACHE=1 to keep no "
            "compiled programs"
        )
    return mb << 20


def kind(mode: int) -> str:
    """What a file of ``st_mode`` ``mode`` is, in a word or two."""
    if stat.S_ISDIR(mode):
        return "a folder"
    if stat.S_ISFIFO(mode):
        return "a FIFO"
    if stat.S_ISCHR(mode) or stat.S_ISBLK(mode):
        return "a device"
    if stat.S_ISSOCK(mode):
        return "a socket"
    if stat.S_ISLNK(mode):
        return "a link"
    return "a regular file" if stat.S_ISREG(mode) else "not a regular file"


def open_regular(path: str | os.PathLike, limit: int, follow: bool = True) -> int:
    """A descriptor of ``path`` opened for reading, after checking that it is a regular
    file of at most ``limit`` bytes (``follow=False``: not a link either). UnfitFile
    otherwise; OSError where it cannot be opened."""
    flags = os.O_RDONLY | _NONBLOCK | _NOCTTY | (0 if follow else _NOFOLLOW)
    try:
        fd = os.open(path, flags)
    except OSError as exc:
        if not follow and os.path.islink(path):
            raise UnfitFile("it is a link") from None
        raise exc
    try:
        st = os.fstat(fd)
        if not stat.S_ISREG(st.st_mode):
            raise UnfitFile(f"it is {kind(st.st_mode)}, not a regular file")
        if st.st_size > limit:
            raise UnfitFile(f"it is {st.st_size:,} bytes, more than the {limit:,} allowed")
    except BaseException:
        os.close(fd)
        raise
    return fd


def read_bytes(path: str | os.PathLike, limit: int, follow: bool = True) -> bytes:
    """The content of the regular file ``path`` (see :func:`open_regular`); at most
    ``limit`` bytes are read even if the file grows meanwhile."""
    fd = open_regular(path, limit, follow)
    with os.fdopen(fd, "rb") as f:
        data = f.read(limit + 1)
    if len(data) > limit:
        raise UnfitFile(f"it grew past {limit:,} bytes while read")
    return data


def read_own(path: str | os.PathLike, limit: int) -> bytes:
    """The content of ``path``, a cache entry: a regular file of at most ``limit`` bytes,
    not a link, that the user owns and no one else may write (UnfitFile otherwise)."""
    fd = open_regular(path, limit, follow=False)
    with os.fdopen(fd, "rb") as f:
        reason = untrusted(os.fstat(fd), "it")
        if reason is not None:
            raise UnfitFile(reason)
        return f.read(limit)


def write_private(path: str | os.PathLike, data: bytes) -> None:
    """Write ``data`` to ``path`` atomically as a ``0600`` file (a temporary file made
    beside it with ``O_EXCL``, renamed over it: a link at ``path`` is replaced, never
    followed), creating missing folders ``0700``."""
    path = Path(path)
    private_folder(path.parent)
    tmp = path.with_name(f".{path.name}.{os.getpid()}.{threading.get_ident()}.tmp")
    try:
        fd = create_new(tmp)
        with os.fdopen(fd, "wb") as f:
            f.write(data)
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(OSError):
            tmp.unlink()
        raise


def read_text(path: str | os.PathLike, limit: int, encoding: str = "utf-8") -> str:
    """The text of the regular file ``path`` (UnicodeDecodeError if it is not text)."""
    return read_bytes(path, limit).decode(encoding)


def check_readable(path: str | os.PathLike, limit: int) -> None:
    """UnfitFile or OSError unless ``path`` is a regular file of at most ``limit`` bytes
    that this process can open for reading."""
    os.close(open_regular(path, limit))


def create_new(path: str | os.PathLike, mode: int = 0o600) -> int:
    """A descriptor of the new file ``path`` opened for writing with exactly ``mode``
    (whatever the umask); FileExistsError if anything, a link included, is there."""
    fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL | _NOFOLLOW, mode)
    try:
        if hasattr(os, "fchmod"):  # the umask may have taken bits off ``mode``
            os.fchmod(fd, mode)
    except BaseException:
        os.close(fd)
        raise
    return fd


def open_lock(path: str | os.PathLike, mode: int = 0o600) -> int:
    """A descriptor of the lock file ``path`` (created with ``mode`` if absent) for
    ``flock``; UnfitFile if a link, a FIFO, a device or a folder is there instead."""
    flags = os.O_RDWR | os.O_CREAT | _NOFOLLOW | _NONBLOCK | _NOCTTY
    try:
        fd = os.open(path, flags, mode)
    except OSError:
        if os.path.islink(path):
            raise UnfitFile(f"lock file {path} is a link; remove it") from None
        raise
    st = os.fstat(fd)
    if not stat.S_ISREG(st.st_mode):
        os.close(fd)
        raise UnfitFile(f"lock file {path} is {kind(st.st_mode)}; remove it")
    return fd


def private_folder(path: str | os.PathLike) -> Path:
    """Create ``path`` and its missing parents with mode ``0700`` whatever the umask (an
    existing folder is left as it is); returns it."""
    path = Path(path)
    missing = []
    p = path
    while not os.path.lexists(p):
        missing.append(p)
        if p.parent == p:
            break
        p = p.parent
    for p in reversed(missing):
        try:
            os.mkdir(p, 0o700)
        except FileExistsError:
            continue  # made meanwhile by another process; checked by untrusted()
        os.chmod(p, 0o700)  # a umask that takes the user's own bits off is undone
    return path


def untrusted(st: os.stat_result, what: str) -> str | None:
    """Why a cache's folder or entry with status ``st`` must not be used (another user
    owns it, or group or others may write it), or None."""
    uid = os.getuid() if hasattr(os, "getuid") else None
    if uid is not None and st.st_uid != uid:
        return f"{what} belongs to another user (uid {st.st_uid})"
    if st.st_mode & (stat.S_IWGRP | stat.S_IWOTH):
        return f"{what} can be written by group or others (mode {stat.S_IMODE(st.st_mode):o})"
    return None


def untrusted_folder(path: str | os.PathLike) -> str | None:
    """Why the cache folder ``path`` must not be used (another user's link or folder, or
    one that group or others may write), or None (absent or not a folder included)."""
    try:
        st = os.lstat(path)
    except (FileNotFoundError, NotADirectoryError):
        return None
    except OSError as exc:
        return f"cache folder {path} cannot be read ({exc.strerror or exc})"
    if stat.S_ISLNK(st.st_mode):
        if hasattr(os, "getuid") and st.st_uid != os.getuid():
            return f"cache folder {path} is a link another user made"
        try:
            st = os.stat(path)  # a link of the user's to a folder of theirs is fine
        except OSError:
            return f"cache folder {path} is a link to nothing"
    if not stat.S_ISDIR(st.st_mode):
        return None  # holds nothing to load; writing into it fails and says so
    return untrusted(st, f"cache folder {path}")
