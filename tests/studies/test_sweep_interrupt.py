"""Ctrl-C on a sweep of a local Dask cluster, as a terminal sends it (SIGINT to every
process of its group, the workers included): one line saying what the study folder kept
and the command that completes it, no traceback, exit code 130; the kept parts stay."""

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from .test_sweep_dask import RESUMABLE

ROOT = Path(__file__).resolve().parents[2]


@pytest.mark.slow  # a local cluster's start: 7 s on an idle machine, more on a busy one
def test_ctrl_c_on_a_sweep_says_what_was_kept_and_how_to_resume(tmp_path):
    (tmp_path / "resumable.toml").write_text(RESUMABLE)
    out = tmp_path / "out"
    env = dict(os.environ, PYTHONPATH=str(ROOT / "src"))
    argv = [sys.executable, "-m", "bristlecrawler.cli.app", "sweep", "resumable.toml"]
    argv += ["--out", "out", "--workers", "2", "--no-progress"]
    proc = subprocess.Popen(
        argv,
        cwd=tmp_path,
        env=env,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        start_new_session=True,  # a process group of its own, as a terminal's job
    )
    deadline = time.monotonic() + 60
    while not list((out / "parts").glob("task-*.npz")) and time.monotonic() < deadline:
        assert proc.poll() is None, proc.communicate()
        time.sleep(0.05)
    os.killpg(proc.pid, signal.SIGINT)
    stdout, stderr = proc.communicate(timeout=60)
    kept = len(list((out / "parts").glob("task-*.npz")))
    assert (proc.returncode, stdout, stderr.count("\n")) == (130, "", 1), stderr
    assert "Traceback" not in stderr and 0 < kept < 20
    assert stderr.startswith(f"interrupted: kept out with {kept} of 20 designs finished")
    assert stderr.rstrip().endswith(
        "complete it with: bristlecrawler sweep resumable.toml --out out --resume"
    )
