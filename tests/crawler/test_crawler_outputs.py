"""Figures, NetCDF and animation of crawler histories (a kinematic stand-in for FE runs)."""

import numpy as np
import pytest

from bristlecrawler.crawler.dataset import crawler_dataset
from bristlecrawler.crawler.history import CrawlerHistory
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


@pytest.mark.slow
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

    from bristlecrawler.crawler import CrawlerSpec, build

    cm = build(CrawlerSpec.paper())
    X = np.asarray(cm.model.params.X)[None, :, :2]
    drawn = SimpleNamespace(lines=cm.lines, line_kind=cm.line_kind, frame_nodes=X)
    chains = CrawlerHistory.bristle_chains(drawn)  # reads lines, line_kind, frame_nodes
    assert [list(c) for c in chains] == [list(b) for b in cm.bristles]


def _with_jointed_bristles(h, kink: float):
    """``h`` with a middle node in each bristle (its bristles are 5 mm long), pushed
    sideways by ``kink`` mm: the two halves turn by 2 atan(kink / 2.5 mm) at a node 3 mm
    thick."""
    import dataclasses

    nodes = h.frame_nodes
    mids = []
    for clamp, tip in ((2, 4), (3, 5)):
        a, b = nodes[:, clamp], nodes[:, tip]
        axis = (b - a) / np.linalg.norm(b - a, axis=1, keepdims=True)
        normal = np.stack([-axis[:, 1], axis[:, 0]], axis=1)
        mids.append(0.5 * (a + b) + kink * normal)
    lines = np.array([[0, 1], [0, 2], [1, 3], [2, 6], [6, 4], [3, 7], [7, 5]])
    return dataclasses.replace(
        h,
        frame_nodes=np.concatenate([nodes, np.stack(mids, axis=1)], axis=1),
        lines=lines,
        line_kind=np.array([0, 1, 1, 2, 2, 2, 2]),
        node_thickness=np.array([0.0, 0.0, 3.0, 3.0, 0.5, 0.5, 3.0, 3.0]),
    )


def test_strain_of_an_arc_is_half_the_thickness_over_the_radius():
    """Points on a circle of radius R: adjacent chords turn by the arc step phi and are
    2 R sin(phi / 2) long, so the strain is h phi / (4 R sin(phi / 2)) -> h / (2 R)."""
    import dataclasses

    R, h_, n = 3.0, 0.4, 12
    phi = np.linspace(0.0, 1.2, n)
    arc = R * np.column_stack([np.sin(phi), 1.0 - np.cos(phi)])
    frames = np.stack([arc * 0.0 + arc[0], arc])  # a point, then the arc
    frames[0, :, 0] = np.linspace(0.0, 1.0, n)  # first frame: straight
    hist = dataclasses.replace(
        kinematic_history(cycles=1, samples=4),
        frame_t=np.array([0.0, 1.0]),
        frame_nodes=frames,
        lines=np.column_stack([np.arange(n - 1), np.arange(1, n)]),
        line_kind=np.full(n - 1, 2),
        node_thickness=np.full(n, h_),
    )
    peak = hist.strain_peak()
    step = phi[1] - phi[0]
    assert peak.t == 1.0 and peak.bristle == 0
    assert peak.strain == pytest.approx(h_ * step / (4 * R * np.sin(step / 2)), rel=1e-12)
    assert peak.turn_deg == pytest.approx(np.degrees(step), rel=1e-12)


@pytest.mark.parametrize(("kink", "warned"), [(0.02, False), (2.0, True)])
def test_a_kinked_bristle_is_reported_in_the_summary(history, kink, warned):
    """A turn of 77 degrees between halves 3.2 mm long at a node 3 mm thick (strain 0.63)
    is flagged with where it is; one of 0.9 degrees (strain 0.007) is not."""
    from bristlecrawler.crawler.history import STRAIN_LIMIT
    from bristlecrawler.jobs.simulate import summarize
    from bristlecrawler.scenario.load import load_scenario

    s = summarize(_with_jointed_bristles(history, kink), load_scenario("paper"))
    assert (s["max_bristle_strain"] > STRAIN_LIMIT) is warned
    assert len(s["warnings"]) == int(warned)
    if warned:
        assert "outside the beam model" in s["warnings"][0] and "node 1" in s["warnings"][0]
        assert "from the end of the gravity step on" in s["warnings"][0]  # kinked throughout


def test_a_strain_peak_below_the_limit_reads_without_a_start():
    from bristlecrawler.crawler.history import StrainPeak

    text = StrainPeak(0.1, 5.0, 1, 3, 2.5).message()
    assert (
        text.startswith("bristle 1 (from the left) turns by 5.0 deg at its node 3")
        and "above" not in text
    )


@pytest.mark.parametrize(("fraction", "warned"), [(0.005, False), (0.02, True)])
def test_a_body_still_moving_after_the_gravity_step_is_reported(history, fraction, warned):
    """The distance the body would still creep after the gravity step against its
    largest advance per cycle: above 1 % the summary warns and names the setting to
    lengthen; below, or not recorded, it does not."""
    import dataclasses

    from bristlecrawler.crawler.history import SETTLE_CREEP_LIMIT

    scale = np.max(np.abs(history.advance_per_cycle()))
    stats = {"settle_speed_mm_s": 0.5, "settle_creep_mm": fraction * scale}
    moving = dataclasses.replace(history, stats={**history.stats, **stats})
    s = moving.summary()
    assert (fraction > SETTLE_CREEP_LIMIT) is warned
    assert s.settle_creep == pytest.approx(fraction * scale)
    assert s.to_dict()["settle_creep_mm"] == s.settle_creep
    assert any("actuation.settle_time" in w for w in s.warnings) is warned
    assert history.unsettled() is None and np.isnan(history.summary().settle_creep)
