"""Provenance of a run: package version, git revision, command, start time."""

from __future__ import annotations

import platform
import subprocess
import sys
import warnings
from dataclasses import dataclass
from pathlib import Path
from typing import Any


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
