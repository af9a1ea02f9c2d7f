"""XLA's C++ log stays off the commands' stderr (its "Very slow compile?" alarm looks like an
error), unless the user asks for it; Python errors still show.

The alarm itself needs a compile of minutes; any ERROR line of XLA's C++ log takes the same
path, and an unusable dump folder gives one at once."""

import os
import subprocess
import sys
from pathlib import Path

from bristlecrawler.cli.app import main

ROOT = Path(__file__).resolve().parents[2]
CODE = (
    "from bristlecrawler.cli.app import quiet_xla\n"
    "quiet_xla()\n"
    "import jax\n"
    "print(float(jax.jit(lambda x: x + 1.0)(1.0)))\n"
)


def _run(level: str | None) -> subprocess.CompletedProcess:
    env = dict(os.environ, PYTHONPATH=str(ROOT / "src"), XLA_FLAGS="--xla_dump_to=/proc/none/x")
    env.pop("TF_CPP_MIN_LOG_LEVEL", None)
    if level is not None:
        env["TF_CPP_MIN_LOG_LEVEL"] = level
    return subprocess.run(
        [sys.executable, "-c", CODE], env=env, capture_output=True, text=True, timeout=120
    )


def test_xla_errors_are_kept_off_stderr():
    p = _run(None)
    assert p.returncode == 0 and p.stdout.strip() == "2.0"
    assert "dump.cc" not in p.stderr, p.stderr[-2000:]


def test_a_level_the_user_set_wins():
    p = _run("0")
    assert p.returncode == 0
    assert "dump.cc" in p.stderr  # the same error line, shown when asked for


def test_the_cli_sets_the_level_before_any_command(monkeypatch):
    monkeypatch.delenv("TF_CPP_MIN_LOG_LEVEL", raising=False)
    try:
        main(["version"])
    except SystemExit:
        pass
    assert os.environ["TF_CPP_MIN_LOG_LEVEL"] == "3"
