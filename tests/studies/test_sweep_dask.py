"""Sweeps on a real Dask cluster: a scheduler and two workers as separate processes on
localhost (``--scheduler``), the LocalCluster default, a client killed half way and
resumed, and workers that die under their tasks."""

import json
import os
import signal
import subprocess
import sys
import time

import numpy as np
import pytest
import xarray as xr

from bristlecrawler.studies import DesignStatus, SweepOptions, evaluate_reduced, run_sweep

from .conftest import worker_env

# 20 designs of the exact solver (three bristles), one task each: long enough to kill
# the client between its first and its last design.
RESUMABLE = """
name = "resumable"
model = "reduced"
reduced_solver = "exact"
chunk = 1
[set]
bristles = 3
cycles = 4
samples_per_cycle = 20000
[axes]
s_max = { linspace = [4.0, 40.0, 10] }
gait = ["breathing", "peristaltic"]
"""


@pytest.fixture(scope="module")
def study(tmp_path_factory):
    path = tmp_path_factory.mktemp("study") / "resumable.toml"
    path.write_text(RESUMABLE)
    return str(path)


@pytest.fixture(scope="module")
def reference(scheduler, study, tmp_path_factory):
    """The study run without interruption on the scheduler's workers."""
    out = tmp_path_factory.mktemp("reference") / "out"
    summary = run_sweep(study, SweepOptions(out=out, scheduler=scheduler, progress=False))
    return summary, out


@pytest.mark.slow
def test_a_sweep_on_a_running_scheduler_runs_every_design(reference):
    summary, out = reference
    assert summary["designs_total"] == summary["designs_done"] == 20
    assert summary["designs_failed"] == summary["designs_lost"] == 0
    ds = xr.open_zarr(out / "study.zarr").load()
    assert dict(ds.sizes) == {"s_max": 10, "gait": 2}
    np.testing.assert_allclose(ds["s_max"], np.linspace(4.0, 40.0, 10))
    assert np.all(ds.status == DesignStatus.DONE)
    # Each stored value is its own design's: rerun one here and compare.
    base = json.loads((out / "study.json").read_text())["base_config"]
    own = evaluate_reduced(base | {"s_max": 24.0, "gait": "peristaltic"})
    stored = ds.sel(s_max=24.0, gait="peristaltic")
    for key in ("net_advance_mm", "work_mJ", "mean_abs_connector_force_N", "steps"):
        assert float(stored[key]) == pytest.approx(own[key], rel=1e-12)
    # Breathing moves every segment at once: more advance per stroke than peristalsis.
    steady = ds.net_advance_mm.sel(s_max=40.0)
    assert float(steady.sel(gait="breathing")) > float(steady.sel(gait="peristaltic")) > 0
    meta = json.loads((out / "meta.json").read_text())
    assert meta["git_revision"] and meta["package_version"] == ds.attrs["package_version"]
    assert (out / "designs.csv").read_text().count("\n") == 21
    assert (out / "figures" / "net_advance_mm.png").stat().st_size > 0


@pytest.mark.slow
def test_a_killed_sweep_resumes_to_the_uninterrupted_store(
    scheduler, study, reference, tmp_path, run_cli
):
    out = tmp_path / "out"
    cmd = [sys.executable, "-m", "bristlecrawler.cli.app", "sweep", study, "--out", str(out)]
    cmd += ["--scheduler", scheduler, "--no-progress", "--no-figures"]
    proc = subprocess.Popen(
        cmd, env=worker_env(), stdout=subprocess.DEVNULL, stderr=subprocess.PIPE
    )
    parts = out / "parts"
    try:
        deadline = time.monotonic() + 120
        while len(list(parts.glob("task-*.npz"))) < 3 and proc.poll() is None:
            assert time.monotonic() < deadline, "the sweep wrote no parts"
            time.sleep(0.02)
        os.kill(proc.pid, signal.SIGKILL)
    finally:
        proc.wait(timeout=30)
    assert proc.returncode == -signal.SIGKILL
    kept = {p.name: p.stat().st_mtime_ns for p in parts.glob("task-*.npz")}
    assert 3 <= len(kept) < 20
    assert not (out / "study.zarr").exists()

    code, _, err = run_cli(["sweep", study, "--out", str(out), "--scheduler", scheduler])
    assert code == 2 and "add --resume" in err
    code, stdout, _ = run_cli(
        ["sweep", study, "--out", str(out), "--scheduler", scheduler, "--resume", "--json"]
    )
    assert code == 0
    summary = json.loads(stdout)
    assert summary["designs_done"] == 20 and summary["tasks_run"] == 20 - len(kept)
    assert {n: (parts / n).stat().st_mtime_ns for n in kept} == kept  # not run again
    got = xr.open_zarr(out / "study.zarr").load().drop_vars("wall_time_s")
    want = xr.open_zarr(reference[1] / "study.zarr").load().drop_vars("wall_time_s")
    xr.testing.assert_identical(got, want)


def _die_once(marker: str) -> dict:
    """Kill the worker the first time (the scheduler then reruns the task elsewhere)."""
    from pathlib import Path

    from bristlecrawler.studies.execute import lost_result

    if not Path(marker).exists():
        Path(marker).touch()
        os._exit(1)
    res = lost_result(1, "")
    res["status"][:] = DesignStatus.DONE
    res["net_advance_mm"][:] = 1.5
    return res


def _die_always() -> dict:
    os._exit(1)


@pytest.mark.slow
def test_a_dead_worker_is_retried_and_designs_are_lost_only_when_retries_run_out(
    scheduler, tmp_path
):
    from distributed import Client

    from bristlecrawler.studies.execute import Task, run_tasks

    got = {}
    with Client(scheduler, timeout=30) as client:
        # One after the other: a worker's death counts against every task queued on it.
        once = Task(0, np.array([0]), _die_once, (str(tmp_path / "died"),))
        run_tasks(client, [once], "dying", lambda t, r: got.setdefault(t.number, r))
        always = Task(1, np.array([1, 2]), _die_always, ())
        run_tasks(client, [always], "dying", lambda t, r: got.setdefault(t.number, r))
        client.wait_for_workers(2, timeout=120)  # the nannies restart them
    assert (tmp_path / "died").exists()
    assert got[0]["status"][0] == DesignStatus.DONE and got[0]["net_advance_mm"][0] == 1.5
    np.testing.assert_array_equal(got[1]["status"], [DesignStatus.LOST] * 2)
    assert "KilledWorker" in got[1]["error"][0]


LOCAL = """
name = "local"
model = "reduced"
[set]
cycles = 3
[axes]
s_max = [10.0, 20.0]
stroke = ["sin2", "triangle"]
"""


@pytest.mark.slow
def test_the_default_local_cluster_and_the_rate_independence_of_the_gait(tmp_path, run_cli):
    """No --scheduler: a LocalCluster of processes. The sin^2 designs take the closed
    forms, the triangle ones the exact solver; the model is rate independent, so both
    strokes give the same advance and work."""
    path = tmp_path / "local.toml"
    path.write_text(LOCAL)
    out = tmp_path / "out"
    code, stdout, _ = run_cli(["sweep", str(path), "--out", str(out), "--json", "--no-figures"])
    assert code == 0
    summary = json.loads(stdout)
    assert summary["designs_total"] == summary["designs_done"] == 4
    assert summary["store"] == str(out / "study.zarr")
    ds = xr.open_zarr(out / "study.zarr").load()
    np.testing.assert_array_equal(ds.steps.sel(stroke="sin2"), [0, 0])
    assert np.all(ds.steps.sel(stroke="triangle") > 0)
    for key in ("net_advance_mm", "work_mJ", "max_abs_connector_force_N"):
        a, b = ds[key].sel(stroke="sin2"), ds[key].sel(stroke="triangle")
        np.testing.assert_allclose(a, b, rtol=1e-9)
