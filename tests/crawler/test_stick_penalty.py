"""The stick penalty is a numerical regularisation: the gait must not depend on it.

`paper` sets `contact.stick_drift = 1e-3` mm (the elastic slip at the friction limit;
the schema's default is 1e-4 mm) because it takes 40 % fewer Newton iterations with the
same gait. Here the same code path on a short, coarse
run: the paper crawler (alpha = 45 deg) on a flat substrate, so that the advance is not
quantised by grooves, 4 elements per bristle, contact at the tips, a 3 mm stroke in 1 s.
Going from 1e-4 to 1e-3 mm must leave the advance unchanged to well below 1 %, while an
elastic slip comparable to the motion (0.1 mm) must change it: the check can tell.
"""

import functools

import pytest

from bristlecrawler.crawler import run
from bristlecrawler.scenario import scenario_from_dict
from bristlecrawler.scenario.convert import to_spec
from bristlecrawler.scenario.load import apply_overrides, load_scenario


@functools.cache
def _advance(drift: float) -> float:
    data = load_scenario("paper").model_dump()
    data["substrate"] = {"kind": "flat"}
    sc = apply_overrides(
        scenario_from_dict(data),
        [
            "bristle.elements=4",
            "contact.nodes='tip'",
            "contact.surface=false",
            "contact.corners=false",
            "actuation.s_max=3.0",
            "actuation.period=1.0",
            "actuation.cycles=1",
            "actuation.settle_time=0.2",
            f"contact.stick_drift={drift!r}",
        ],
    )
    return run(to_spec(sc)).net_advance


@pytest.mark.slow
def test_the_gait_does_not_depend_on_a_small_stick_drift():
    fine, paper = _advance(1e-4), _advance(1e-3)
    # The inclined bristles move the crawler along the grain even on a flat substrate.
    assert fine > 0.05
    assert paper == pytest.approx(fine, rel=5e-3)


@pytest.mark.slow
def test_an_elastic_slip_comparable_to_the_motion_changes_it():
    fine, coarse = _advance(1e-4), _advance(0.1)
    assert abs(coarse - fine) > 0.1 * fine
