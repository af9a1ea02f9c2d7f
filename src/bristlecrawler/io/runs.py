"""Run folders: ``runs/<id>/`` with the resolved configuration, version and git revision."""

from __future__ import annotations

import datetime as _dt
import json
import math
import os
import platform
import subprocess
import sys
import warnings
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from bristlecrawler.errors import InputError
from bristlecrawler.io.atomic import atomic_write_text


@dataclass(frozen=True)
class RunInfo:
    """Provenance of a run."""

    run_id: str
    version: str
    git_revision: str
    started: str
    command: str

    def as_dict(self) -> dict[str, Any]:
        return {
            "run_id": self.run_id,
            "package_version": self.version,
            "git_revision": self.git_revision,
            "started_utc": self.started,
            "command": self.command,
            "python": sys.version.split()[0],
            "platform": platform.platform(),
        }


def git_revision() -> str:
    """Git revision of the source tree this package was imported from ("+dirty" if modified),
    or "unknown" outside a git checkout."""
    here = Path(__file__).resolve().parent
    # JAX warns when a threaded process forks; git is exec'd at once, so the warning would
    # not apply (Python 3.11 spawns it without the fork hooks; later versions may not).
    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", message=r"os\.fork\(\) was called")
        return _git_revision(here)


def _git_revision(here: Path) -> str:
    try:
        rev = subprocess.run(
            ["git", "rev-parse", "HEAD"], cwd=here, capture_output=True, text=True, timeout=5
        )
        if rev.returncode != 0:
            return "unknown"
        dirty = subprocess.run(
            ["git", "status", "--porcelain", "--untracked-files=no"],
            cwd=here,
            capture_output=True,
            text=True,
            timeout=5,
        )
        return rev.stdout.strip() + ("+dirty" if dirty.stdout.strip() else "")
    except (OSError, subprocess.SubprocessError):
        return "unknown"


def check_out_dir(out: str | os.PathLike | None) -> None:
    """InputError, before any work, if ``out`` cannot take a new run: it is a file, a
    parent of it is a file or not writable, or it already holds a run (``meta.json``; a
    new run there would mix its files with the old run's). None (``runs/<id>``) passes."""
    if out is None:
        return
    path = Path(out)
    if path.exists() and not path.is_dir():
        raise InputError(f"output path {path} exists and is not a folder")
    if path.is_symlink() and not path.exists():
        raise InputError(f"output path {path} is a link to nothing")
    if (path / "meta.json").exists():
        raise InputError(
            f"output folder {path} already holds a run (meta.json); give another --out "
            "or remove it first"
        )
    parent = path.absolute()
    while not parent.exists():
        parent = parent.parent
    if not parent.is_dir():
        raise InputError(f"cannot create output folder {path}: {parent} is not a folder")
    if not os.access(parent, os.W_OK | os.X_OK):
        raise InputError(f"cannot create output folder {path}: {parent} is not writable")


def prepare_run_dir(out: str | os.PathLike | None, kind: str, root: str = "runs") -> Path:
    """Create and return the output folder: ``out`` if given, else ``runs/<timestamp>-<kind>``.

    Refuses what :func:`check_out_dir` refuses (a file, a folder holding a run). Files of
    the new run replace any others of the same name atomically.
    """
    if out is not None:
        check_out_dir(out)
        path = Path(out)
        path.mkdir(parents=True, exist_ok=True)
        return path
    stamp = _dt.datetime.now(_dt.UTC).strftime("%Y%m%d-%H%M%S")
    base = Path(root) / f"{stamp}-{kind}"
    path, i = base, 1
    while path.exists():
        path = base.with_name(f"{base.name}-{i}")
        i += 1
    path.mkdir(parents=True)
    return path


def json_safe(value: Any) -> Any:
    """``value`` with every non-finite float written as the string ``"inf"``, ``"-inf"`` or
    ``"nan"`` (JSON has no such numbers; Python's ``Infinity`` is not JSON)."""
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


def write_run_metadata(run_dir: Path, config: dict[str, Any], command: str) -> RunInfo:
    """Write ``config.json`` (resolved configuration, strict JSON: an infinite bound is the
    string ``"inf"``) and ``meta.json`` (provenance)."""
    from bristlecrawler import __version__

    info = RunInfo(
        run_id=run_dir.name,
        version=__version__,
        git_revision=git_revision(),
        started=_dt.datetime.now(_dt.UTC).isoformat(timespec="seconds"),
        command=command,
    )
    atomic_write_text(run_dir / "config.json", config_json(config) + "\n")
    atomic_write_text(run_dir / "meta.json", json.dumps(info.as_dict(), indent=2) + "\n")
    return info
