"""The stick penalty is a numerical regularisation: the gait must not depend on it.

`paper` sets `contact.stick_drift = 1e-3` mm (the elastic slip at the friction limit;
the schema's default is 1e-4 mm) because it takes 40 % fewer Newton iterations with the
same gait. Here the same code path on a short, coarse
run: the paper crawler (alpha = 45 deg) on a flat substrate, so that the advance is not
quantised by grooves, 4 elements per bristle, contact at the tips, a 3 mm stroke in 1 s,
after a gravity step long enough for the crawler to come to rest. Going from 1e-4 to
1e-3 mm may change the advance only by the elastic slips the drift allows (each of the
two tips sticks and slips once a cycle: at most four drifts), while an elastic slip
comparable to the motion (0.1 mm) must change it: the check can tell. A gravity step cut
short starts the stroke from a crawler still sliding, and the run says so.
"""

import functools

import pytest

from bristlecrawler.crawler import run
from bristlecrawler.scenario import scenario_from_dict
from bristlecrawler.scenario.convert import to_spec
from bristlecrawler.scenario.load import apply_overrides, load_scenario


@functools.cache
def _run(drift: float, settle: float = 1.0):
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
            f"actuation.settle_time={settle!r}",
            f"contact.stick_drift={drift!r}",
        ],
    )
    return run(to_spec(sc))


def _advance(drift: float) -> float:
    return _run(drift).net_advance


@pytest.mark.slow
def test_the_gait_does_not_depend_on_a_small_stick_drift():
    fine, paper = _advance(1e-4), _advance(1e-3)
    # The inclined bristles move the crawler along the grain even on a flat substrate.
    assert fine > 0.05
    assert abs(paper - fine) <= 4 * (1e-3 - 1e-4)
    assert _run(1e-4).unsettled() is None and _run(1e-3).unsettled() is None


@pytest.mark.slow
def test_an_elastic_slip_comparable_to_the_motion_changes_it():
    fine, coarse = _advance(1e-4), _advance(0.1)
    assert abs(coarse - fine) > 0.1 * fine


@pytest.mark.slow
def test_a_gravity_step_cut_short_is_reported():
    """After 0.2 s the crawler's body still slides (its tips splay under the weight):
    the summary names the setting to lengthen."""
    h = _run(1e-4, settle=0.2)
    assert h.stats["settle_speed_mm_s"] > 10 * _run(1e-4).stats["settle_speed_mm_s"]
    assert "actuation.settle_time" in h.unsettled()
