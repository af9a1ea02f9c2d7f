"""A study's figures as a researcher would publish them: on a grid of many designs, a few
labelled slices against each axis (no cloud of points, no empty legend) and a design map
with labelled contours, every axis named with its unit."""

import warnings

import matplotlib
import numpy as np
import pytest

matplotlib.use("Agg")
import matplotlib.pyplot as plt

from bristlecrawler.studies import runner, store
from bristlecrawler.studies.evaluate import OUTPUTS, DesignStatus
from bristlecrawler.studies.figures import (
    MAX_LINES,
    _against_axis,
    _map,
    axis_label,
    output_label,
)

STUDY = """
name = "grid"
model = "reduced"
[axes]
s_max = { linspace = [1.0, 40.0, 20] }
fp = { linspace = [0.05, 2.0, 15] }
"""


@pytest.fixture(scope="module")
def grid(tmp_path_factory):
    """300 designs on a 20 x 15 grid, each output a smooth function of the design."""
    import xarray as xr

    tmp_path = tmp_path_factory.mktemp("grid")
    path = tmp_path / "study.toml"
    path.write_text(STUDY)
    p = runner.plan(str(path))
    out = tmp_path / "out"
    store.start_folder(out, p.resolved, {})
    n = p.designs.n
    ramp = np.linspace(0.0, 1.0, n)
    result = {k: np.sin(3.0 * ramp) + ramp for k in OUTPUTS}
    result["status"] = np.full(n, int(DesignStatus.DONE), np.int8)
    result["error"] = np.array([""] * n)
    store.write_part(out, 0, np.arange(n), result)
    meta = {"package_version": "0", "git_revision": "x"}
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # matplotlib's "No artists with labels" among them
        runner._finish(p, out, meta, runner.SweepOptions(out=out, figures=True), 1, 1.0)
    return xr.open_zarr(out / "study.zarr").load()


@pytest.mark.parametrize(("key", "other", "unit"), [("s_max", "fp", "N"), ("fp", "s_max", "mm")])
def test_many_designs_against_an_axis_are_a_few_labelled_slices(grid, key, other, unit):
    fig, ax = plt.subplots()
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        _against_axis(ax, grid, "advance_per_cycle_mm", key)
    lines = ax.get_lines()
    assert 2 <= len(lines) <= MAX_LINES
    labels = [ln.get_label() for ln in lines]
    assert all(lab.startswith(f"{other} = ") and lab.endswith(f" {unit}") for lab in labels)
    assert ax.get_legend() is not None and len(ax.get_legend().get_texts()) == len(lines)
    assert ax.get_xlabel() == axis_label(key) and "(" in ax.get_xlabel()
    plt.close(fig)


def test_the_design_map_has_labelled_contours_and_named_axes(grid):
    fig, ax = plt.subplots()
    _, _, handles = _map(ax, grid, "advance_per_cycle_mm", "s_max", "fp")
    contours = [c for c in ax.collections if c.__class__.__name__ == "QuadContourSet"]
    assert contours and len(ax.texts) > 0  # the contour labels
    assert handles == [] and ax.get_legend() is None  # every design has a value: no legend
    plt.close(fig)
    assert output_label("advance_per_cycle_mm") == "advance per cycle (mm)"
