"""The files of the stored programs: entries that cannot carry someone else's code.

An entry holds a serialised executable whose trees are pickled, and unpickling runs code.
So an entry is loaded only when

* its folder and the cache folder above it belong to the user and no one else may write
  them, and the entry itself is a regular file of the user's that no one else may write
  (as OpenSSH treats its keys), opened without following a link;
* it carries an HMAC-SHA256 of its file name and content under a secret key only the
  user can read (``$BRISTLECRAWLER_CACHE_KEY``, default
  ``$XDG_CONFIG_HOME/bristlecrawler/cache-key``, made ``0600`` on first use). The name is
  part of what is authenticated: an entry moved or copied to another program's name is
  refused rather than run with arguments it was not compiled for.

Anything else is one warning, then the program is compiled as if the entry were absent.
Folders are created ``0700`` and entries ``0600`` whatever the umask; a lock file that is a
link, a FIFO or a device is never written through.
"""

from __future__ import annotations

import contextlib
import functools
import hashlib
import hmac
import os
import pickle
import secrets
import socket
import sys
import threading
import time
import warnings
from pathlib import Path

from bristlecrawler._files import (
    UnfitFile,
    create_new,
    open_lock,
    open_regular,
    private_folder,
    read_own,
    untrusted,
    untrusted_folder,
    write_private,
    xdg_home,
)
from bristlecrawler.fe.cache_size import evict

MAGIC = b"bristlecrawler-program-2\n"
#: The largest entry read back (the paper crawler's are tens of MB).
MAX_ENTRY_BYTES = 2**31
_TAG = 32
_WARNED: set[str] = set()
# Loading executables from several threads at once crashes jaxlib (segmentation fault in
# deserialize_and_load); loads take milliseconds, so they go one at a time.
LOAD_LOCK = threading.Lock()

#: How long a process waits for another one compiling the same program before it compiles
#: the program itself (s): a compile takes minutes on a busy machine, never hours.
LOCK_WAIT_S = 1800.0


class CacheWarning(UserWarning):
    """The compiled-program cache could not store or load a program (the run goes on)."""


def warn_once(kind: str, message: str) -> None:
    if kind not in _WARNED:
        _WARNED.add(kind)
        warnings.warn(message, CacheWarning, stacklevel=3)


def key_path() -> Path:
    """Where the secret key that authenticates the entries is kept."""
    given = os.environ.get("BRISTLECRAWLER_CACHE_KEY", "").strip()
    if given:
        return Path(given).expanduser()
    return xdg_home("XDG_CONFIG_HOME", ".config") / "bristlecrawler" / "cache-key"


@functools.lru_cache(maxsize=4)
def _secret(path: Path) -> bytes | None:
    """The key at ``path``, made if absent; None (with one warning) where it cannot be
    made or others could read or replace it."""
    try:
        if not os.path.lexists(path):
            _make_key(path)
        fd = open_regular(path, 4096, follow=False)
        try:
            st = os.fstat(fd)
            key = os.read(fd, 4096).strip()
        finally:
            os.close(fd)
        reason = untrusted(st, f"cache key {path}")
        if reason is None and st.st_mode & 0o077:
            reason = f"cache key {path} can be read by group or others (chmod 600 it)"
        if reason is None and len(key) < 32:
            reason = f"cache key {path} is too short (remove it: a new one is made)"
    except OSError as exc:
        reason = (
            f"cache key {path} cannot be used ({exc.strerror or exc}; "
            "BRISTLECRAWLER_CACHE_KEY names another file)"
        )
    if reason is not None:
        warn_once("key", f"{reason}; compiled programs are neither loaded nor stored")
        return None
    return key


def secret() -> bytes | None:
    return _secret(key_path())


def _make_key(path: Path) -> None:
    """Write a new random key at ``path`` (0600) unless another process made one first."""
    private_folder(path.parent)
    tmp = path.with_name(f".{path.name}.{os.getpid()}.{threading.get_ident()}.tmp")
    fd = create_new(tmp)
    try:
        os.write(fd, secrets.token_hex(32).encode() + b"\n")
        os.fsync(fd)
    finally:
        os.close(fd)
    try:
        os.link(tmp, path)  # fails if a key (or anything) is there: then it is used
    except FileExistsError:
        pass
    finally:
        os.unlink(tmp)


def _tag(key: bytes, name: str, payload: bytes) -> bytes:
    mac = hmac.new(key, name.encode() + b"\0", hashlib.sha256)
    mac.update(payload)
    return mac.digest()


def untrusted_store(folder: Path) -> str | None:
    """Why the entries in ``folder`` must not be loaded (see the module), or None."""
    for p in (folder.parent, folder):
        reason = untrusted_folder(p)
        if reason is not None:
            return reason
    return None


def read_entry(path: Path, deserialize):
    """The executable stored at ``path`` (``deserialize(data, in_tree, out_tree)`` loads
    it), or None: absent, or refused with one warning (see the module) and removed
    where it is the user's to remove."""
    reason = untrusted_store(path.parent)
    if reason is not None:
        warn_once("folder", f"{reason}; its compiled programs are not loaded (chmod 700 it)")
        return None
    key = secret()
    if key is None:
        return None
    try:
        blob = read_own(path, MAX_ENTRY_BYTES)
    except (FileNotFoundError, NotADirectoryError):
        return None
    except OSError as exc:
        return _refuse(path, str(exc.strerror or exc))
    if not blob.startswith(MAGIC) or len(blob) < len(MAGIC) + _TAG:
        return _refuse(path, "not a stored program")
    tag, payload = blob[len(MAGIC) : len(MAGIC) + _TAG], blob[len(MAGIC) + _TAG :]
    if not hmac.compare_digest(tag, _tag(key, path.name, payload)):
        return _refuse(path, "its signature does not match (damaged, moved or not yours)")
    with contextlib.suppress(OSError):
        # Its last use, as its access time (the modification time says when it was
        # written): past the size limit, the least recently used entries go first.
        written = os.stat(path, follow_symlinks=False).st_mtime_ns
        os.utime(path, ns=(time.time_ns(), written), follow_symlinks=False)
    try:
        data, in_tree, out_tree = pickle.loads(payload)
        with LOAD_LOCK:
            return deserialize(data, in_tree, out_tree)
    except Exception as exc:  # signed by the user, yet written by another jaxlib
        return _refuse(path, f"cannot be loaded ({type(exc).__name__})")


def _refuse(path: Path, why: str) -> None:
    warn_once(
        f"entry:{why[:20]}",
        f"compiled program {path.name} not loaded: {why}; compiling it again",
    )
    with contextlib.suppress(OSError):
        if not os.path.isdir(path):
            path.unlink()  # the folder is the user's: never follows a link
    return None


def write_entry(path: Path, serialized, name: str) -> None:
    """Store ``serialized`` (the executable's data and trees) at ``path`` atomically, a
    ``0600`` file in ``0700`` folders, signed with the user's key."""
    key = secret()
    if key is None or untrusted_store(path.parent) is not None:
        return
    payload = pickle.dumps(serialized)
    try:
        write_private(path, MAGIC + _tag(key, path.name, payload) + payload)
    except OSError as exc:
        warn_once(
            "write",
            f"compiled-program cache {path.parent} not writable ({exc.strerror or exc}); "
            "the FE programs are compiled in every process",
        )
        return
    evict(path.parent.parent, keep=path)


@contextlib.contextmanager
def entry_lock(path: Path, name: str = "a program"):
    """Hold an exclusive lock on ``path``'s entry while it is compiled and written (an
    advisory ``flock`` on a file beside it, which names its holder; the system releases
    it when a process dies). A process that finds it held says who holds it and waits,
    at most :data:`LOCK_WAIT_S`, then says it gives up and goes on without it (the worst
    case is a program compiled twice), as where there is no ``flock`` or no lock file."""
    try:
        import fcntl

        if untrusted_store(path.parent) is not None:
            raise OSError("untrusted folder")
        private_folder(path.parent)
        fd = open_lock(path.with_suffix(".lock"))
    except UnfitFile as exc:  # a link or a FIFO planted there: never written through
        warn_once("lock", f"{exc}; compiling without it")
        yield
        return
    except (ImportError, OSError):
        yield
        return
    try:
        if _wait(fd, fcntl, path, name):
            os.ftruncate(fd, 0)
            os.pwrite(fd, f"{os.getpid()} {socket.gethostname()}\n".encode(), 0)
        yield
    finally:
        os.close(fd)  # releases the lock


def _wait(fd: int, fcntl, path: Path, name: str) -> bool:
    """Take the lock within LOCK_WAIT_S; True if taken."""
    deadline = time.monotonic() + LOCK_WAIT_S
    said = False
    while True:
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            return True
        except BlockingIOError:
            pass
        except OSError:
            return False
        if time.monotonic() >= deadline:
            _say(
                f"gave up waiting for the lock on compiled program {name} after "
                f"{LOCK_WAIT_S:g} s; compiling it here"
            )
            return False
        if not said:
            said = True
            holder = os.pread(fd, 300, 0).decode(errors="replace").split()
            who = "another process"
            if holder and holder[0].isdigit():
                who = f"process {holder[0]}" + (f" on {holder[1][:64]}" if holder[1:] else "")
            _say(
                f"{who} is compiling program {name} (lock {path.with_suffix('.lock')}); "
                f"waiting for it, at most {LOCK_WAIT_S:g} s"
            )
        time.sleep(0.2)


def _say(line: str) -> None:
    # At once on stderr, not as a warning: the CLI shows warnings only when a run ends.
    print(line, file=sys.stderr, flush=True)
