"""Run a command on a pseudo-terminal, as a user at a terminal would, and read what it
shows (stdout and stderr together, terminal control sequences included)."""

import os
import pty
import select
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def under_a_terminal(argv: list[str], columns: int = 120, env: dict | None = None) -> str:
    """What ``argv`` (``python`` is this interpreter) writes on a pseudo-terminal
    ``columns`` wide."""
    leader, follower = pty.openpty()
    full = dict(os.environ, PYTHONPATH=str(ROOT / "src"), COLUMNS=str(columns), TERM="xterm")
    full.pop("NO_COLOR", None)
    full.pop("FORCE_COLOR", None)
    full.update(env or {})
    if argv[0] == "python":
        argv = [sys.executable, *argv[1:]]
    proc = subprocess.Popen(argv, stdin=follower, stdout=follower, stderr=follower, env=full)
    os.close(follower)
    chunks = []
    while True:
        ready, _, _ = select.select([leader], [], [], 60)
        if not ready:
            break
        try:
            data = os.read(leader, 65536)
        except OSError:  # the child closed the terminal
            break
        if not data:
            break
        chunks.append(data)
    proc.wait(timeout=60)
    os.close(leader)
    return b"".join(chunks).decode("utf-8", "replace").replace("\r\n", "\n")


def cli(*args: str) -> list[str]:
    """The argv of ``bristlecrawler args`` with this interpreter."""
    return ["python", "-m", "bristlecrawler.cli.app", *args]
