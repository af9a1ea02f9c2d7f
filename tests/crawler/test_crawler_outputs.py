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
        np.testing.assert_array_equal(ds["node_thickness"], history.node_thickness)
        assert all("long_name" in ds[v].attrs for v in ds.data_vars)


def test_figures_and_animation(history, tmp_path):
    for name, fig in (
        ("d", vc.plot_delta_vs_s(history)),
        ("c", vc.plot_connector(history)),
        ("s", vc.plot_shapes(history)),
    ):
        assert save_figure(fig, tmp_path / f"{name}.png").stat().st_size > 1000
    gif = vc.animate(history, tmp_path / "anim")[0]
    assert gif.stat().st_size > 1000


def test_bristle_outline_lies_half_the_thickness_either_side_of_the_axis():
    """On a circular axis of radius R the faces are the circles R +- h/2 (interior points,
    where the axis's central difference is the exact tangent; the end points' one-sided
    differences are chords, off by half a step)."""
    R, n = 4.0, 41
    phi = np.linspace(0.1, 1.4, n)
    x = R * np.column_stack([np.cos(phi), np.sin(phi)])
    h = np.linspace(3.0, 0.5, n)
    out = vc._outline(x, h)
    r_plus = np.linalg.norm(out[:n], axis=1)
    r_minus = np.linalg.norm(out[n:][::-1], axis=1)
    np.testing.assert_allclose(r_plus[1:-1] - R, -0.5 * h[1:-1], rtol=1e-12)  # inner side
    np.testing.assert_allclose(r_minus[1:-1] - R, 0.5 * h[1:-1], rtol=1e-12)
    np.testing.assert_allclose(np.abs(r_plus[[0, -1]] - R), 0.5 * h[[0, -1]], rtol=1e-3)


def test_bristle_chains_are_read_back_from_the_drawing_clamp_to_tip():
    from types import SimpleNamespace

    from bristlecrawler.crawler.model import build_crawler
    from bristlecrawler.scenario.load import load_scenario

    cm = build_crawler(load_scenario("paper"))
    X = np.asarray(cm.model.params.X)[None, :, :2]
    drawn = SimpleNamespace(lines=cm.lines, line_kind=cm.line_kind, frame_nodes=X)
    chains = vc._bristles(drawn)
    assert [list(c) for c in chains] == [list(b) for b in cm.bristles]
