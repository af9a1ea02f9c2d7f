"""The closed-loop SMA actuator model and the quasi-static assumption of the reduced model."""

import numpy as np
import pytest

from bristlecrawler.errors import InputError
from bristlecrawler.experiment import SMAActuator, run_sma
from bristlecrawler.reduced import ReducedCrawler, SampledStroke, solve


@pytest.fixture(scope="module")
def response():
    return run_sma(SMAActuator(), cycles=3)


def test_cycles_last_about_twenty_seconds_and_hit_the_target(response):
    p = SMAActuator()
    assert 15.0 < response.cycle_durations[0] < 25.0
    for a, b in zip(response.cycle_starts[:-1], response.cycle_starts[1:], strict=True):
        assert response.s[a:b].max() >= p.s_target  # current switched off at s~
        assert response.s[a:b].max() < p.s_target + 0.2  # ... with little overshoot
    assert response.s[response.cycle_starts[-1]] <= p.s_rest


def test_heating_before_transformation_matches_the_exponential(response):
    p = SMAActuator()
    P = 1e3 * p.resistance * p.current**2  # mW
    tau = p.heat_capacity / p.conductance
    mask = (response.temperature < p.A_s - 0.5) & (response.t < response.t[1] + 5.0)
    mask &= np.arange(response.t.size) < np.argmax(response.temperature > p.A_s)
    t = response.t[mask]
    exact = p.T_ambient + P / p.conductance * (1 - np.exp(-t / tau))
    np.testing.assert_allclose(response.temperature[mask], exact, atol=0.02)


def test_phase_fraction_is_hysteretic(response):
    p = SMAActuator()
    xi, T = response.xi, response.temperature
    assert np.all((xi >= 0) & (xi <= 1))
    # Martensite fraction only falls while current flows and only rises while it is off.
    dxi = np.diff(xi)
    on = response.current[:-1] > 0
    assert np.all(dxi[on & (T[1:] > T[:-1])] <= 1e-12)
    assert np.all(dxi[~on & (T[1:] < T[:-1])] >= -1e-12)
    # No transformation below A_s on heating: xi = 1 there.
    assert np.all(xi[(T < p.A_s) & (np.arange(T.size) < np.argmax(T > p.A_s))] == 1.0)


def test_reduced_gait_depends_on_the_stroke_turning_points_only(response):
    """Quasi-static check: the SMA history (flat top, uneven speeds) and a piecewise-linear
    stroke through the same turning points give the same Delta at every turning point."""
    crawler = ReducedCrawler.two_bristle()
    stroke = response.stroke()
    full = solve(crawler, stroke.t, stroke.s)
    ds = np.diff(stroke.s)
    turning = (
        [0]
        + [i for i in range(1, ds.size) if ds[i - 1] * ds[i] < 0 or (ds[i - 1] != 0 and ds[i] == 0)]
        + [stroke.s.size - 1]
    )
    turning = np.unique(turning)
    lin = SampledStroke(np.arange(turning.size, dtype=float), stroke.s[turning])
    coarse = solve(crawler, lin.t, lin.s)
    np.testing.assert_allclose(coarse.delta, full.delta[turning], atol=1e-9)
    assert full.energy_balance_error < 1e-9


def test_bad_parameters():
    with pytest.raises(InputError, match="beyond the actuator's reach"):
        SMAActuator(s_target=40.0)
    with pytest.raises(InputError, match="temperatures"):
        SMAActuator(M_s=50.0, A_s=45.0)
    with pytest.raises(InputError, match="current"):
        SMAActuator(current=0.0)
