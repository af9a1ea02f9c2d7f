"""What a sweep with failed designs says and draws: the failed designs listed last with
their reasons, exit code 1, every figure marking them, axis labels from the declarations,
and an ETA from the finished designs' measured times. No Dask: the parts a sweep's tasks
write are written here, then gathered and drawn as a sweep does."""

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt
import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from bristlecrawler.studies import runner, store
from bristlecrawler.studies.evaluate import OUTPUTS, DesignStatus
from bristlecrawler.studies.figures import _against_axis, axis_label, fit_title, output_label
from bristlecrawler.studies.progress import eta_seconds

STUDY = """
name = "inclination-like"
model = "reduced"
[axes]
fp = [0.2, 0.3, 0.45, 0.6]
"""
WHY = "solver failed: stroke near t = 12.3 s: Newton did not converge; dt cut below dt_min"


@pytest.fixture(scope="module")
def finished(tmp_path_factory):
    """A study of four designs, the third failed, gathered and drawn: (summary, folder)."""
    tmp_path = tmp_path_factory.mktemp("sweep")
    path = tmp_path / "study.toml"
    path.write_text(STUDY)
    p = runner.plan(str(path))
    out = tmp_path / "out"
    store.start_folder(out, p.resolved, {})
    n = p.designs.n
    result = {k: np.linspace(1.0, 2.0, n) for k in OUTPUTS}
    result["status"] = np.full(n, int(DesignStatus.DONE), np.int8)
    result["status"][2] = DesignStatus.FAILED
    result["error"] = np.array(["", "", WHY, ""])
    for k in OUTPUTS:
        result[k][2] = np.nan
    store.write_part(out, 0, np.arange(n), result)
    meta = {"package_version": "0", "git_revision": "x"}
    opts = runner.SweepOptions(out=out, figures=True)
    return runner._finish(p, out, meta, opts, 1, 1.0), out


def test_the_summary_lists_the_failed_design_with_its_reason(finished):
    summary, _ = finished
    assert summary["designs_failed"] == 1
    assert summary["failures"] == [
        {"design": 2, "label": "design 2 (fp=0.45)", "status": "failed", "error": WHY}
    ]


def test_the_cli_ends_with_the_failures_and_exit_code_1(finished, run_cli, monkeypatch):
    summary, _ = finished
    monkeypatch.setattr(runner, "run_sweep", lambda study, options: summary)
    code, out, err = run_cli(["sweep", "inclination", "--no-progress"])
    assert code == 1
    lines = err.strip().splitlines()
    assert lines[-2] == f"design 2 (fp=0.45) failed: {WHY}"
    assert lines[-1].startswith("error: 1 of 4 designs not done (1 failed, 0 lost)")
    assert "designs" in out  # the summary table still printed


def test_a_sweep_without_failures_exits_0_silently(finished, run_cli, monkeypatch):
    summary, _ = finished
    clean = summary | {"failures": [], "designs_failed": 0, "designs_done": 4}
    monkeypatch.setattr(runner, "run_sweep", lambda study, options: clean)
    code, _, err = run_cli(["sweep", "inclination", "--no-progress"])
    assert code == 0 and err == ""


def test_the_json_summary_keeps_the_exit_code(finished, run_cli, monkeypatch):
    import json

    summary, _ = finished
    monkeypatch.setattr(runner, "run_sweep", lambda study, options: summary)
    code, out, _ = run_cli(["sweep", "inclination", "--json"])
    assert code == 1 and json.loads(out)["failures"][0]["design"] == 2


def test_every_panel_marks_the_failed_design_at_its_axis_value(finished):
    import xarray as xr

    _, out = finished
    ds = xr.open_zarr(out / "study.zarr").load()
    for name in ("net_advance_mm", "work_mJ"):
        fig, ax = plt.subplots()
        _against_axis(ax, ds, name, "fp")
        marks = [ln for ln in ax.get_lines() if ln.get_label() == "failed (no value)"]
        assert len(marks) == 1 and list(marks[0].get_xdata()) == [0.45]
        assert ax.get_xlabel() == "F_p, resistance along the grain (N)"
        assert ax.get_ylabel() == output_label(name)
        plt.close(fig)
    assert sorted(p.name for p in (out / "figures").iterdir())  # the figures were written


def test_axis_labels_come_from_the_declarations():
    assert axis_label("bristle.alpha_deg") == "inclination from the vertical (degrees)"
    assert axis_label("substrate.pitch").endswith("(mm)")
    assert axis_label("not.a.key") == "not.a.key"
    assert output_label("net_advance_mm") == "net advance (mm)"
    assert output_label("cost_of_transport_mJ_per_mm") == "cost of transport (mJ/mm)"
    assert output_label("mean_abs_connector_force_N") == "mean |connector force| (N)"


@given(st.text(alphabet="abc def", min_size=0, max_size=300), st.floats(2.0, 20.0))
def test_titles_are_wrapped_to_the_figure(text, width):
    wrapped = fit_title(text, width)
    limit = max(int(width * 72 / (0.55 * 9)), 20)
    assert all(len(line) <= limit for line in wrapped.splitlines())
    assert wrapped.split() == text.split()


def test_the_eta_comes_from_the_measured_design_times():
    assert eta_seconds(4, [], 2) is None  # nothing measured yet
    assert eta_seconds(0, [100.0], 2) == 0.0
    # The first designs compiled (600 s); the median of the rest sets the pace.
    assert eta_seconds(4, [600.0, 60.0, 50.0], 2) == pytest.approx(2 * 60.0)
    assert eta_seconds(3, [60.0, float("nan")], 1) == pytest.approx(180.0)
