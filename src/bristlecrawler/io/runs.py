"""Run folders as transactions: claimed before any work, complete or absent, never mixed.

A run that writes a folder (``reduced``, ``simulate``, ``analyze``) goes through
:func:`claim_run_dir`, which returns a :class:`RunFolder`:

1. **Claim.** After the input is validated and before any solving, the target's lock file
   ``.<name>.lock`` beside it is locked (``flock``; the kernel releases it when the process
   ends, however it ends). A second run into the same folder is refused at once, as is a
   folder that already holds a run (unless ``replace``) or that holds other files, and a
   path through one of the names below (:data:`~.output_paths.RESERVED_NAME`).
2. **Write.** The files go into a hidden sibling ``.<name>.partial-XXXXXXXX``.
3. **Commit.** ``meta.json`` with ``"status": "complete"`` is written last, then the
   folder is renamed into place (over an old run only with ``replace``). A reader never
   sees a folder with the files of two runs, or a half-written one marked complete.

A process killed mid-run leaves its partial folder and lock file; the next run into the
same folder removes them and says so. Interrupted (Ctrl-C) after its results file was
written, a run keeps the folder with ``"status": "interrupted"``; such a folder, like any
without ``"status": "complete"``, is reported as incomplete and replaced only on request.
"""

from __future__ import annotations

import datetime as _dt
import json
import math
import os
import re
import shutil
import socket
import tempfile
from pathlib import Path
from typing import Any

from bristlecrawler._files import create_new, open_lock, read_bytes
from bristlecrawler.errors import InputError, Interrupted
from bristlecrawler.io.atomic import atomic_write_text
from bristlecrawler.io.jsonio import dumps_strict
from bristlecrawler.io.output_paths import (
    check_new_file,
    check_not_reserved,
    check_parent,
    folder_in,
    output_folder,
    shown,
    why,
)
from bristlecrawler.io.provenance import RunInfo, git_revision

#: The largest ``meta.json`` or lock file read (bytes; a run's is under 2 kB).
_MAX_META_BYTES = 1 << 20
#: ``meta.json`` "status" of a run whose every file was written.
COMPLETE = "complete"
#: ... of a run that is being written (seen only in its partial folder).
RUNNING = "running"
#: ... of a run stopped by Ctrl-C after its results file was written.
INTERRUPTED = "interrupted"

__all__ = [
    "COMPLETE",
    "INTERRUPTED",
    "RUNNING",
    "RunFolder",
    "RunInfo",
    "check_new_file",
    "check_out_dir",
    "claim_run_dir",
    "git_revision",
    "run_status",
]


def _now() -> str:
    return _dt.datetime.now(_dt.UTC).isoformat(timespec="seconds")


def run_status(path: str | os.PathLike) -> str | None:
    """State of a folder: None (absent or empty), ``"complete"``, ``"running"``,
    ``"interrupted"``, ``"unknown"`` (a ``meta.json`` that says nothing readable) or
    ``"other"`` (files, but no run)."""
    path = Path(path)
    if not path.is_dir() or not any(path.iterdir()):
        return None
    meta = path / "meta.json"
    if not meta.exists():
        return "other"
    try:
        doc = json.loads(read_bytes(meta, _MAX_META_BYTES, follow=False))
    except (OSError, ValueError):
        return "unknown"
    status = doc.get("status") if isinstance(doc, dict) else None
    if status is None and ((path / "summary.json").exists() or (path / "analysis.json").exists()):
        return COMPLETE  # written before runs recorded their status
    return status if isinstance(status, str) else "unknown"


def check_out_dir(out: str | os.PathLike | None, replace: bool = False) -> None:
    """InputError unless ``out`` can take a new run (see :func:`claim_run_dir`); a quick
    check without claiming, for commands that read large inputs first."""
    if out is None:
        return
    check_not_reserved(out, _WRITING)
    path = output_folder(Path(out))
    check_parent(path)
    _check_state(path, replace)


#: The partial folders of the runs this process is writing (real paths): a run may hold
#: the runs it writes itself (``reproduce`` writes its design studies inside its folder).
_WRITING: set[str] = set()


def _check_not_nested(path: Path) -> None:
    """InputError if ``path`` lies inside another run's folder: a run folder is a unit,
    replaced or removed whole, and a run inside it would go with it."""
    for above in Path(os.path.realpath(path)).parents:
        if str(above) in _WRITING:
            return
        if (above / "meta.json").exists() and run_status(above) not in (None, "other"):
            raise InputError(
                f"output folder {shown(path)} is inside the run in {shown(above)}; give a "
                "folder outside it"
            )


def _check_state(path: Path, replace: bool) -> None:
    _check_not_nested(path)
    status = run_status(path)
    if status is None:
        return
    if status == "other":
        raise InputError(
            f"output folder {path} is not empty and holds no run (no meta.json); give a new "
            "or empty folder"
        )
    if replace:
        return
    if status == COMPLETE:
        raise InputError(
            f"output folder {path} already holds a run (meta.json); give another --out, or "
            "--replace to replace it"
        )
    raise InputError(
        f"output folder {path} holds an incomplete run (status: {status}); give another "
        "--out, or --replace to replace it"
    )


class _Lock:
    """An exclusive ``flock`` on ``path``, taken without waiting."""

    def __init__(self, path: Path) -> None:
        self.path = path
        try:
            import fcntl
        except ImportError:  # no flock (Windows): an exclusive create, not freed by a crash
            try:
                self.fd = create_new(path, 0o644)
            except FileExistsError:
                raise BlockingIOError(f"{path} exists") from None
            return
        while True:
            # Never through a link, nor on a FIFO or a device: UnfitFile names what is there.
            fd = open_lock(path, 0o644)
            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except BlockingIOError:
                os.close(fd)
                raise
            # The holder before us may have removed the file after we opened it: then our
            # lock is on a file nobody else will open; take the one now at the path.
            try:
                same = os.stat(path).st_ino == os.fstat(fd).st_ino
            except FileNotFoundError:
                same = False
            if same:
                self.fd = fd
                return
            os.close(fd)

    def write(self, text: str) -> None:
        os.ftruncate(self.fd, 0)
        os.pwrite(self.fd, text.encode(), 0)

    def release(self) -> None:
        if self.fd < 0:
            return
        try:
            self.path.unlink()
        except FileNotFoundError:
            pass
        os.close(self.fd)
        self.fd = -1


class RunFolder:
    """A claimed output folder (see the module). Use it as a context manager; write files
    under :attr:`path`; on a normal exit the folder is committed to :attr:`target`."""

    def __init__(self, target: Path, lock: _Lock, replace: bool, notes: list[str]) -> None:
        self.target = target
        self.replace = replace
        self.notes = notes
        self._lock = lock
        self._results: str | None = None
        self._meta: dict[str, Any] = {"run_id": target.name, "status": RUNNING}
        self.path = Path(tempfile.mkdtemp(prefix=f".{target.name}.partial-", dir=target.parent))
        self._writing = os.path.realpath(self.path)
        try:
            os.chmod(self.path, 0o777 & ~_umask())
        except BaseException:  # Ctrl-C included: no partial folder without its run
            self.discard()
            raise
        _WRITING.add(self._writing)

    def __enter__(self) -> RunFolder:
        return self

    def write_metadata(self, config: dict[str, Any], command: str) -> RunInfo:
        """Write ``config.json`` (resolved configuration) and ``meta.json`` (provenance,
        ``"status": "running"`` until :meth:`commit`)."""
        from bristlecrawler import __version__

        info = RunInfo(self.target.name, __version__, git_revision(), _now(), command)
        self._meta = info.as_dict() | {"status": RUNNING}
        atomic_write_text(self.path / "config.json", config_json(config) + "\n")
        self.write_json("meta.json", self._meta)
        return info

    def write_json(self, name: str, value: Any) -> Path:
        """Write strict JSON (no NaN or Infinity) to ``name`` in the folder, atomically."""
        return atomic_write_text(self.path / name, dumps_strict(value, indent=2) + "\n")

    def results_written(self, name: str) -> None:
        """Say that the main results file is complete: an interrupted run keeps it."""
        self._results = name

    def commit(self, status: str = COMPLETE) -> None:
        """Mark the run ``status`` (meta.json, written last) and rename it into place."""
        self._meta = self._meta | {"status": status, "finished_utc": _now()}
        self.write_json("meta.json", self._meta)
        if self.target.exists() and any(self.target.iterdir()):
            old = Path(tempfile.mkdtemp(prefix=f".{self.target.name}.old-", dir=self.target.parent))
            os.rename(self.target, old)  # replaces the empty folder mkdtemp made
            os.rename(self.path, self.target)
            shutil.rmtree(old, ignore_errors=True)
        else:
            if self.target.exists():
                os.rmdir(self.target)  # empty; rename over a folder is not portable
            os.rename(self.path, self.target)
        self.path = self.target

    def discard(self) -> None:
        if self.path != self.target:
            shutil.rmtree(self.path, ignore_errors=True)

    def __exit__(self, kind, exc, tb) -> None:
        _WRITING.discard(self._writing)
        try:
            if exc is None:
                self.commit()
                return
            if not isinstance(exc, KeyboardInterrupt | Interrupted):
                self.discard()
                return
            message = self._interrupted()
        finally:
            self._lock.release()
        raise (Interrupted if isinstance(exc, Interrupted) else KeyboardInterrupt)(
            message
        ) from None

    def _interrupted(self) -> str:
        """Keep what an interrupted run can keep; one line saying what that is."""
        if self._results is not None and run_status(self.target) is None:
            self.commit(INTERRUPTED)
            kept = ", ".join(sorted(p.name for p in self.target.iterdir()))
            return (
                f"interrupted: kept {self.target} ({kept}), marked incomplete; rerun with "
                "--replace to replace it"
            )
        self.discard()
        if run_status(self.target) is not None:
            return f"interrupted: {self.target} left as it was, nothing of this run kept"
        return f"interrupted: nothing written to {self.target}"


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def _recover(target: Path) -> list[str]:
    """Clear what a killed run into ``target`` left beside it (the caller holds the lock,
    so no live run owns these): partial folders, and an old run moved aside by a replace
    that was killed between its two renames (put back if the new run never arrived)."""
    notes = []
    pattern = re.compile(rf"^\.{re.escape(target.name)}\.(partial|old)-[a-z0-9_]{{8}}$")
    for p in sorted(target.parent.iterdir()):
        m = pattern.match(p.name)
        if not m or not p.is_dir() or p.is_symlink():
            continue
        if m.group(1) == "old" and not target.exists():
            os.rename(p, target)
            notes.append(f"restored the run in {target} that an interrupted --replace had moved")
        else:
            shutil.rmtree(p, ignore_errors=True)
            notes.append(f"removed {p.name}, the partial files of a run that was killed")
    return notes


def claim_run_dir(
    out: str | os.PathLike | None,
    kind: str,
    root: str | os.PathLike = "runs",
    replace: bool = False,
    command: str = "",
) -> RunFolder:
    """Claim the output folder of a new run (see the module): ``out``, or
    ``<root>/<timestamp>-<kind>`` when None (with a suffix -1, -2, ... if that is taken;
    InputError if ``kind`` would place it anywhere but directly inside ``root``).

    Raises InputError, before any work and without changing anything, when another run is
    writing into the folder, when it holds a run (complete or not; ``replace`` replaces it
    once the new run is complete), holds other files, or cannot be created.
    """
    if out is not None:
        check_not_reserved(out, _WRITING)
        return _claim(output_folder(Path(out)), replace, command)
    stamp = _dt.datetime.now(_dt.UTC).strftime("%Y%m%d-%H%M%S")
    base = folder_in(root, f"{stamp}-{kind}")  # before anything is created
    for i in range(1000):
        target = base if i == 0 else folder_in(root, f"{base.name}-{i}")
        if target.exists():
            continue
        try:
            return _claim(target, False, command)
        except _Taken:
            continue  # another run started in the same second
    raise InputError(f"no free run folder name in {root} for {base.name}")


class _Taken(InputError):
    """The folder is being written by another run."""


def _claim(target: Path, replace: bool, command: str) -> RunFolder:
    check_parent(target)
    _check_state(target, replace)  # refuse without touching anything; checked again locked
    try:
        target.parent.mkdir(parents=True, exist_ok=True)
        lock = _Lock(target.parent / f".{target.name}.lock")
    except BlockingIOError:
        raise _Taken(
            f"output folder {target} is being written by another run{_owner(target)}; "
            "wait for it to finish or give another --out"
        ) from None
    except OSError as exc:
        raise InputError(f"cannot create output folder {shown(target)}: {why(exc)}") from None
    try:
        notes = _recover(target)
        _check_state(target, replace)
        owner = {
            "pid": os.getpid(),
            "host": socket.gethostname(),
            "started_utc": _now(),
            "command": command,
        }
        lock.write(dumps_strict(owner))
        return RunFolder(target, lock, replace, notes)
    except BaseException:
        lock.release()
        raise


def _owner(target: Path) -> str:
    try:
        lock = target.parent / f".{target.name}.lock"
        doc = json.loads(read_bytes(lock, _MAX_META_BYTES, follow=False))
        return f" (pid {doc['pid']} on {doc['host']}, since {doc['started_utc']})"
    except (OSError, ValueError, KeyError, TypeError):
        return ""


def json_safe(value: Any) -> Any:
    """``value`` with every non-finite float written as the string ``"inf"``, ``"-inf"`` or
    ``"nan"`` (JSON has no such numbers; Python's ``Infinity`` is not JSON). For resolved
    configurations, where an infinite bound is a setting, not a missing number."""
    if isinstance(value, float) and not math.isfinite(value):
        return "nan" if math.isnan(value) else ("inf" if value > 0 else "-inf")
    if isinstance(value, dict):
        return {k: json_safe(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [json_safe(v) for v in value]
    return value


def config_json(config: dict[str, Any], indent: int | None = 2) -> str:
    """Strict JSON of a resolved configuration (see :func:`json_safe`)."""
    return json.dumps(json_safe(config), indent=indent, default=str, allow_nan=False)
