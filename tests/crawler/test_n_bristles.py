"""Crawlers with N bristles: the spec's checks, the assembly, and a short run of three."""

import dataclasses
import functools
import importlib.util
import pathlib
import sys

import numpy as np
import pytest

from bristlecrawler.crawler import Actuation, Bristle, Contact, CrawlerSpec, build
from bristlecrawler.crawler.model import stretches
from bristlecrawler.errors import InputError

PAPER = CrawlerSpec.paper()


def _coarse(spec: CrawlerSpec, elements: int = 4) -> CrawlerSpec:
    return spec.replace_bristles(elements=elements)


@pytest.mark.parametrize(
    ("change", "words"),
    [
        ({"bristles": (Bristle(position=0.0),)}, "at least 2 bristles"),
        ({"bristles": (Bristle(position=0.0), Bristle(position=120.0))}, "outside the body"),
        ({"bristles": (Bristle(position=0.0), Bristle(position=0.0))}, "two bristles at one"),
        ({"bristles": (Bristle(position=50.0), Bristle(position=10.0))}, "out of order"),
        ({"bristles": (Bristle(alpha_deg=85.0), Bristle(position=100.0))}, "alpha_deg"),
        ({"bristles": (Bristle(length=0.0), Bristle(position=100.0))}, "bristles[0].length"),
        ({"bristles": (Bristle(), Bristle(position=100.0, width=-1.0))}, "bristles[1].width"),
        ({"actuation": Actuation(s_max=99.0)}, "into each other"),
        ({"contact": Contact(mu=-0.1)}, "contact.mu"),
    ],
)
def test_a_design_that_cannot_be_built_is_one_line_naming_it(change, words):
    spec = dataclasses.replace(PAPER, **change)
    with pytest.raises(InputError, match=words.replace("[", r"\[").replace("]", r"\]")) as err:
        build(spec)
    assert "\n" not in str(err.value)


def test_more_bristles_share_the_stroke_room_of_a_shorter_segment():
    """Four bristles on 100 mm leave 33 mm segments: a 30 mm stroke brings neighbouring
    bristles into each other (their tips trail by 3.5 mm, their clamps are 3 mm thick),
    though it fits between two bristles 100 mm apart."""
    spec = dataclasses.replace(PAPER, actuation=Actuation(s_max=30.0))
    build(_coarse(spec))
    with pytest.raises(InputError, match="bristles 0 and 1"):
        build(_coarse(spec.with_bristles(4)))


@pytest.mark.parametrize("n", [2, 3, 4])
def test_the_body_carries_its_mass_and_each_segment_its_actuator(n):
    spec = _coarse(PAPER.with_bristles(n))
    cm = build(spec)
    X = np.asarray(cm.model.params.X)
    np.testing.assert_allclose(X[list(cm.body), 0], np.linspace(0.0, 100.0, n), atol=1e-12)
    assert len(set(X[list(cm.body), 1])) == 1  # a level body
    assert len(cm.subtrees) == n - 1 and len(cm.tips) == n
    for j, sub in enumerate(cm.subtrees):
        # The actuator of segment j pushes everything beyond it, and nothing before it.
        beyond = {k for i in range(j + 1, n) for k in (cm.body[i], *cm.bristles[i])}
        assert set(sub) == beyond
    # Every tip starts just touching the top of the substrate.
    np.testing.assert_allclose(X[list(cm.tips), 1] - 0.25 * np.sin(np.pi / 4), -1e-3, atol=1e-9)


def test_breathing_and_peristaltic_gaits_drive_the_segments_as_in_the_reduced_model():
    import bristlecrawler as bc

    a = Actuation(s_max=10.0, period=4.0, cycles=2, settle_time=0.5, gait="peristaltic", lag=1.0)
    spec = dataclasses.replace(PAPER.with_bristles(4), actuation=a)
    t = np.linspace(0.0, 12.0, 97)
    got = np.stack([-np.asarray(f(t + a.settle_time)) for f in stretches(spec)], axis=1)
    gait = bc.peristaltic(bc.Sin2Stroke(10.0, 4.0), 3, lag=1.0)
    np.testing.assert_allclose(got, gait.shortenings(t, cycles=2), atol=1e-12)
    assert spec.actuation.stroke_duration(3) == pytest.approx(gait.duration(2))
    breathing = dataclasses.replace(spec, actuation=dataclasses.replace(a, gait="breathing"))
    values = [np.asarray(f(t)) for f in stretches(breathing)]
    assert all(np.array_equal(values[0], v) for v in values[1:])


def _example():
    path = pathlib.Path(__file__).parents[2] / "examples" / "n_bristle_crawler.py"
    spec = importlib.util.spec_from_file_location("n_bristle_crawler", path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # its dataclasses look their module up
    spec.loader.exec_module(module)
    return module


@functools.cache
def _three():
    """A short, coarse three-bristle run (the example's code path), held at rest for half a
    second after its stroke."""
    from bristlecrawler.crawler import DEFAULT_STAGES, Hold
    from structures import three_bristles

    return _example().compare(3, three_bristles(), stages=(*DEFAULT_STAGES, Hold(0.5)))


@pytest.mark.slow
def test_three_bristles_advance_and_every_segment_does_work():
    """It advances like the reduced model's crawler, and the energy balance closes only
    with the work of both actuators (the second one's share is far from zero)."""
    row = _three()
    assert row.fe_per_cycle[0] > 1.0 and row.reduced_per_cycle[0] > 1.0
    assert row.balance_error < 0.2
    h = row.history
    ds = h.to_dataset()
    assert ds.sizes["segment"] == 2 and ds.sizes["bristle"] == 3
    s, f = h.segment_shortening, h.segment_force
    works = np.sum(0.5 * (f[1:] + f[:-1]) * np.diff(s, axis=0), axis=0)
    assert works.sum() == pytest.approx(h.connector_work[-1], rel=1e-12)
    assert works[1] > 0.2 * works.sum()


@pytest.mark.slow
def test_a_hold_after_the_stroke_records_a_crawler_at_rest():
    """A user stage after the stroke: with the actuators at rest no work is done and the
    crawler, standing on its bristles, stays where it is."""
    h = _three().history
    hold = h.t > 4.0 + 1e-9
    assert h.t[-1] == pytest.approx(4.5) and hold.sum() > 2
    assert np.ptp(h.connector_work[hold]) < 1e-6 * abs(h.connector_work[-1])
    assert np.ptp(h.delta[hold]) < 0.05  # mm
