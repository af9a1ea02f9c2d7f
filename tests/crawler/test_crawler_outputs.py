"""Figures, NetCDF and animation of crawler histories (a kinematic stand-in for FE runs)."""

import numpy as np
import pytest

from bristlecrawler.io.crawler_dataset import crawler_dataset
from bristlecrawler.io.netcdf import write_netcdf
from bristlecrawler.viz import crawler as vc
from bristlecrawler.viz.reduced import save_figure

from .kinematic import kinematic_history


@pytest.fixture(scope="module")
def history():
    return kinematic_history()


def test_history_bookkeeping(history):
    assert history.advance_per_cycle().size == 2
    assert history.advance_per_cycle().sum() == pytest.approx(history.net_advance)
    assert history.energy_balance_rel_error() < 1e-9


def test_dataset_round_trip(history, tmp_path):
    import xarray as xr

    path = write_netcdf(crawler_dataset(history, {"scenario": "test"}), tmp_path / "h.nc")
    with xr.open_dataset(path) as ds:
        np.testing.assert_allclose(ds["delta"], history.delta)
        assert ds["connector_force"].attrs["units"] == "N"
        assert ds.attrs["scenario"] == "test" and ds.attrs["cycles"] == 2
        assert ds.sizes["frame"] == history.frame_t.size


def test_figures_and_animation(history, tmp_path):
    for name, fig in (
        ("d", vc.plot_delta_vs_s(history)),
        ("c", vc.plot_connector(history)),
        ("s", vc.plot_shapes(history)),
    ):
        assert save_figure(fig, tmp_path / f"{name}.png").stat().st_size > 1000
    gif = vc.animate(history, tmp_path / "anim")[0]
    assert gif.stat().st_size > 1000
