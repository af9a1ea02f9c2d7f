"""Bad substrate and friction parameters are refused at construction with one-line messages."""

import numpy as np
import pytest

from bristlecrawler.contact import CoulombLaw, Grooves, Polyline, Sawtooth
from bristlecrawler.errors import InputError
from bristlecrawler.scenario import scenario_from_dict
from bristlecrawler.scenario.substrate import SUBSTRATE_KINDS, parse_substrate

GroovesConfig = SUBSTRATE_KINDS["grooves"]


def _refused(match, fn, *args, **kwargs):
    with pytest.raises(InputError, match=match) as exc:
        fn(*args, **kwargs)
    assert "\n" not in str(exc.value)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"width": 0.0, "depth": 0.25, "pitch": 2.0}, "width"),
        ({"width": 1.0, "depth": -0.1, "pitch": 2.0}, "depth"),
        ({"width": 1.0, "depth": 0.25, "pitch": 0.0}, "pitch"),
        ({"width": 2.0, "depth": 0.25, "pitch": 2.0}, "width .* pitch"),
        ({"width": 1.0, "depth": 0.25, "pitch": 2.0, "fillet_bottom": 0.6}, "fillet_bottom"),
        ({"width": 1.0, "depth": 0.25, "pitch": 2.0, "fillet_top": 0.3}, "fillet_top"),
        ({"width": 1.0, "depth": 0.25, "pitch": 2.0, "fillet_top": -0.1}, "fillet_top"),
        (
            {"width": 1.0, "depth": 0.25, "pitch": 2.0, "fillet_top": 0.2, "fillet_bottom": 0.1},
            "fillet_top \\+ fillet_bottom",
        ),
        ({"width": 1.9, "depth": 0.5, "pitch": 2.0, "fillet_top": 0.1}, "land"),
        ({"width": float("nan"), "depth": 0.25, "pitch": 2.0}, "width"),
    ],
)
def test_grooves_refused(kwargs, match):
    _refused(match, Grooves, **kwargs)


def test_grooves_batch_checked_elementwise():
    _refused("width", Grooves, width=np.array([0.5, 2.5]), depth=0.25, pitch=2.0)


@pytest.mark.parametrize(
    ("points", "match"),
    [
        ([[0, 0], [1, 0.5], [2, 0.1]], "not periodic"),
        ([[0, 0], [1, 0.5], [0.5, 0.2], [2, 0]], "x decreases"),
        ([[0, 0], [0, -1], [0, -0.5], [2, 0]], "folds back"),
        ([[0, 0], [1, 0], [1, 0], [2, 0]], "coincide"),
        ([[0, 0], [0, 1]], "period"),
        ([[0, 0, 0], [1, 0, 0]], "shape"),
    ],
)
def test_polyline_refused(points, match):
    _refused(match, Polyline, points=points)


def test_sawtooth_refused():
    _refused("rise_fraction", Sawtooth, pitch=1.0, height=0.2, rise_fraction=1.5)
    _refused("height", Sawtooth, pitch=1.0, height=0.0)


def test_negative_friction_coefficient_refused():
    _refused("mu", CoulombLaw, mu=-0.1, k_n=1.0, k_t=1.0)
    _refused("k_t", CoulombLaw, mu=0.1, k_n=1.0, k_t=0.0)
    _refused("mu", CoulombLaw.for_reference_load, mu=-1.0)
    _refused("contact.mu", scenario_from_dict, {"contact": {"mu": -0.2}})


def test_toml_table_builds_and_refuses():
    cfg = parse_substrate({"kind": "grooves", "width": 1.0, "depth": 0.25, "pitch": 2.0})
    assert isinstance(cfg, GroovesConfig)
    g = cfg.build()
    assert float(g.width) == 1.0 and float(g.pitch) == 2.0
    assert "mm" in GroovesConfig.model_fields["width"].description
    poly = parse_substrate({"kind": "polyline", "points": [[0, 0], [1, 1], [2, 0]]}).build()
    assert poly.points.shape == (3, 2)
    _refused("kind", parse_substrate, {"kind": "bumps"})
    _refused("width", parse_substrate, {"kind": "grooves", "width": -1, "depth": 1, "pitch": 2})
    _refused("colour", parse_substrate, {"kind": "flat", "colour": "red"})
    _refused("pitch", parse_substrate, {"kind": "grooves", "width": 3, "depth": 1, "pitch": 2})
    _refused("not periodic", parse_substrate, {"kind": "polyline", "points": [[0, 0], [1, 1]]})
