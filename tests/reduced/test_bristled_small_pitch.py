"""The small-pitch limit of a tip dragged over a texture (Gidoni & DeSimone, arXiv
1602.05611): with the facets' slopes fixed and the period shrinking, the mean drag force
of a tip on the bristled model's tip path, under a dead load and pulled by a spring,
converges to a rate-independent friction law that depends on the direction of sliding:
the resistance of the facet it climbs, W (sin + mu cos) / (cos - mu sin)."""

import numpy as np
import pytest

from bristlecrawler.reduced.bristled.drag import (
    climbing_resistance,
    drag_force,
    sawtooth,
    tip_path,
)

MU, LOAD, STIFFNESS = 0.65, 0.2, 1.0  # -, N, N/mm
PITCHES = (1.0, 0.5, 0.25, 0.125, 0.0625)  # mm
RISE, DROP = 20.0, 40.0  # the facets' slopes, degrees


def _forces(backwards: bool, stiffness: float = STIFFNESS) -> np.ndarray:
    # The tip's radius scales with the period (1 %), so that the limit is the texture's,
    # not the tip's size.
    return np.array(
        [
            drag_force(
                tip_path(sawtooth(p, RISE, DROP), 0.01 * p),
                MU,
                LOAD,
                stiffness,
                backwards=backwards,
            )
            for p in PITCHES
        ]
    )


@pytest.mark.parametrize(("backwards", "slope"), [(False, RISE), (True, DROP)])
def test_the_drag_force_converges_to_the_climbed_facets_resistance(backwards, slope):
    exact = float(climbing_resistance(slope, MU, LOAD))
    error = exact - _forces(backwards)
    # Below the limit, first order in the period: the spring's stretch varies by k p.
    assert np.all(error > 0)
    order = np.log2(error[:-1] / error[1:])
    assert order == pytest.approx(np.ones_like(order), abs=0.1)
    assert error[-1] / exact < 0.03
    # Richardson's extrapolation of the two finest periods: the closed form.
    limit = 2.0 * (exact - error[-1]) - (exact - error[-2])
    assert limit == pytest.approx(exact, rel=2e-3)


def test_the_limit_is_directional_and_does_not_depend_on_the_spring():
    forward, backward = _forces(False)[-1], _forces(True)[-1]
    ratio = float(climbing_resistance(DROP, MU, LOAD) / climbing_resistance(RISE, MU, LOAD))
    assert ratio > 2.0
    assert backward / forward == pytest.approx(ratio, rel=0.03)
    stiffer = _forces(False, stiffness=4.0 * STIFFNESS)[-1]
    exact = float(climbing_resistance(RISE, MU, LOAD))
    # A stiffer spring only makes the period's part larger, the limit is the same.
    assert abs(exact - stiffer) == pytest.approx(4.0 * abs(exact - forward), rel=0.1)


def test_a_facet_steeper_than_the_friction_angles_complement_locks():
    steep = 90.0 - np.degrees(np.arctan(MU)) + 1.0
    path = tip_path(sawtooth(0.5, RISE, steep), 0.005)
    assert np.isinf(drag_force(path, MU, LOAD, STIFFNESS, backwards=True))
    assert np.isfinite(drag_force(path, MU, LOAD, STIFFNESS))
