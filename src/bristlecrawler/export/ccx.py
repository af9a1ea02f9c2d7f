"""Running CalculiX (``ccx``) on a deck and reading what it printed.

CalculiX reads the ABAQUS dialect; Debian and Ubuntu package it as ``calculix-ccx``. A
static analysis that reaches a limit point (a tip that snaps over a groove's wall) stops
with "too many cutbacks" or "increment size smaller than minimum": the increments before
it are converged and are kept, and :class:`CcxRun` says where it stopped.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import time
from dataclasses import dataclass
from pathlib import Path

from bristlecrawler.errors import InputError, SolverError
from bristlecrawler.export.results import Printed, read_dat

INSTALL_HINT = (
    "CalculiX (ccx) is not on the PATH: install it (Debian/Ubuntu: "
    "sudo apt-get install calculix-ccx; conda: conda install -c conda-forge calculix) "
    "or name it with BRISTLECRAWLER_CCX"
)

_STOPS = ("too many cutbacks", "increment size smaller than minimum", "divergence")


def find_ccx() -> str:
    """The ``ccx`` executable (``BRISTLECRAWLER_CCX`` or the PATH); InputError if none."""
    named = os.environ.get("BRISTLECRAWLER_CCX")
    exe = shutil.which(named) if named else shutil.which("ccx")
    if exe is None:
        raise InputError(
            INSTALL_HINT if not named else f"BRISTLECRAWLER_CCX={named!r} is not an executable"
        )
    return exe


@dataclass(frozen=True)
class CcxRun:
    """A finished CalculiX run: its printed blocks, whether it reached the end, the line
    where it stopped otherwise, the last time it converged (s) and the wall time (s)."""

    printed: dict[tuple[str, str], Printed]
    complete: bool
    stopped: str
    wall_s: float
    version: str


def run_ccx(folder: Path, job: str, timeout_s: float = 1800.0, exe: str | None = None) -> CcxRun:
    """Run ``ccx -i job`` in ``folder`` (``job.inp`` there). A run that stops early keeps
    its converged increments; one that prints nothing raises :class:`SolverError`."""
    exe = exe or find_ccx()
    t0 = time.perf_counter()
    try:
        proc = subprocess.run(
            [exe, "-i", job],
            cwd=folder,
            capture_output=True,
            text=True,
            timeout=timeout_s,
            env=os.environ | {"OMP_NUM_THREADS": os.environ.get("OMP_NUM_THREADS", "1")},
        )
    except subprocess.TimeoutExpired as exc:
        raise SolverError(f"CalculiX ran past {timeout_s:g} s on {folder / job}.inp") from exc
    wall = time.perf_counter() - t0
    log = proc.stdout + proc.stderr
    (folder / f"{job}.log").write_text(log)
    dat = folder / f"{job}.dat"
    printed = read_dat(dat.read_text()) if dat.exists() else {}
    errors = [line.strip() for line in log.splitlines() if "*ERROR" in line]
    stop = next((s for s in _STOPS if s in log), "")
    if not printed:
        first = errors[0] if errors else f"exit code {proc.returncode}"
        raise SolverError(f"CalculiX printed no results for {job}.inp ({first}; see {job}.log)")
    complete = proc.returncode == 0 and not errors
    stopped = "" if complete else (stop or (errors[0] if errors else f"exit {proc.returncode}"))
    return CcxRun(printed, complete, stopped, wall, _version(exe))


def _version(exe: str) -> str:
    try:
        out = subprocess.run([exe, "-v"], capture_output=True, text=True, timeout=30).stdout
    except (OSError, subprocess.SubprocessError):
        return "unknown"
    m = re.search(r"Version\s+(\S+)", out)
    return m.group(1) if m else "unknown"
