"""The frictional-contact verification cases of ``bristlecrawler verify`` (issue #4), run
through the FE solver once per test process (:func:`default_runs`, shared with the FE
verification test) and checked against their independent references.

Tolerances are the error budgets of :mod:`bristlecrawler.verification.contact_rows`.
"""

import math

import numpy as np
import pytest

from bristlecrawler.contact import SLIP, STICK
from bristlecrawler.verification.contact_refs import (
    DEFAULT_OSCILLATOR,
    integrate_coulomb_oscillator,
)
from bristlecrawler.verification.contact_rows import contact_rows, default_runs


@pytest.fixture(scope="module")
def runs():
    return default_runs()


# -- Coulomb oscillator (HHT, dt = 1 ms) --------------------------------------------------


@pytest.mark.slow
def test_oscillator_turning_points_match_the_closed_form(runs):
    run = runs.oscillator
    ref = run.reference
    assert run.turning_points.size == ref.positions.size == 6
    # second-order position error per reversal: (2 mu g dt)^2 / (2 |a|) + 2 x stick drift
    np.testing.assert_allclose(run.turning_points, ref.positions, rtol=0, atol=1e-4 * 100.0)


@pytest.mark.slow
def test_oscillator_turning_points_match_an_event_driven_integrator(runs):
    # The same ODE integrated by scipy with events: independent of the closed form.
    ode = integrate_coulomb_oscillator(DEFAULT_OSCILLATOR, t_end=3.0)
    np.testing.assert_allclose(runs.oscillator.turning_points, ode.positions, atol=1e-2)


@pytest.mark.slow
def test_oscillator_stop_time(runs):
    # phase shifts of the four reversals inside a step and in the stick zone: 2.8e-3
    run = runs.oscillator
    assert run.stop_time == pytest.approx(run.reference.stop_time, rel=3e-3)
    # the first half period has no reversal before it: second order in dt
    assert run.turning_times[1] == pytest.approx(math.pi / DEFAULT_OSCILLATOR.omega, rel=1e-4)


@pytest.mark.slow
def test_oscillator_dissipation_accounts_for_the_lost_spring_energy(runs):
    run = runs.oscillator
    assert run.energy_balance_rel_error < 1e-4


# -- block on an incline -------------------------------------------------------------------


@pytest.mark.slow
def test_incline_push_ratio(runs):
    run = runs.incline
    assert run.ratio == pytest.approx(run.reference, rel=1e-4)
    assert run.first_slip_step > 0
    assert run.travel_after_onset > 0.0  # it slides up the slope, not down


# -- pressed-and-dragged bristle -------------------------------------------------------------


@pytest.mark.slow
def test_pressed_bristle_matches_the_linearised_answer(runs):
    run = runs.pressed
    ref = run.reference
    assert not ref.slips_on_press and not ref.self_locks
    assert run.drag_at_slip == pytest.approx(ref.drag_at_slip, rel=1e-3)
    assert run.normal_at_press == pytest.approx(ref.normal_at_press, rel=1e-3)
    assert run.normal_in_slip == pytest.approx(ref.normal_in_slip, rel=1e-3)


@pytest.mark.slow
def test_pressed_bristle_deviation_is_first_order_in_the_press(runs):
    # The FE beam is geometrically nonlinear: its deviation from the linear answer per unit
    # press halves with the press (that is what the extrapolation removes).
    run = runs.pressed
    ref = run.reference
    for key in ("drag_at_slip", "normal_in_slip"):
        per_press = getattr(ref, key)  # reference at the full press
        e_full = run.raw[0][key] / per_press - 1.0
        e_half = 2.0 * run.raw[1][key] / per_press - 1.0
        assert abs(e_full) > 1e-3
        assert 1.8 < e_full / e_half < 2.2, (key, e_full, e_half)


# -- bristle tip dragged across grooves ------------------------------------------------------


@pytest.mark.slow
def test_grooved_drag_energy_balance(runs):
    run = runs.grooved
    assert run.balance_rel_error < 1e-3
    E = run.energies
    assert E["work_in"][-1] > 0 and E["friction"][-1] > 0 and E["damping"][-1] > 0
    # friction dissipation never decreases
    assert np.all(np.diff(E["friction"]) >= -1e-15)


@pytest.mark.slow
def test_grooved_drag_drops_into_and_climbs_out_of_every_groove(runs):
    run = runs.grooved
    assert run.grooves_passed == 2
    assert run.grooves_entered == run.climbs == run.grooves_passed
    # it slides on the lands and flies free over the grooves
    assert np.any(run.states == SLIP) and np.any(run.states == 0)
    assert np.any(run.states == STICK)


@pytest.mark.slow
def test_grooved_drag_forces_stay_finite(runs):
    run = runs.grooved
    assert np.all(np.isfinite(run.p_n)) and np.all(np.isfinite(run.f_t))
    assert run.max_penetration < 1e-4  # the penalty's design value at 1 N
    # Coulomb: the tangential force never exceeds mu p_N (mu = 0.65)
    assert np.all(np.abs(run.f_t) <= 0.65 * run.p_n * (1 + 1e-9) + 1e-12)


# -- verify rows and JSON --------------------------------------------------------------------


@pytest.mark.slow
def test_verify_rows_pass_and_json_has_the_issue_keys(runs):
    rows, doc = contact_rows(runs)
    failed = [
        f"{r.case}: {r.quantity} err {r.error:.2e} > {r.tol:.0e}" for r in rows if not r.passed
    ]
    assert not failed, failed
    assert len(doc["coulomb_oscillator_turning_points_mm"]) == 6
    assert doc["coulomb_oscillator_stop_time_s"] > 0
    assert doc["incline_push_ratio"] == pytest.approx(0.4123711, rel=1e-4)
    assert {"pressed_bristle_drag", "grooved_drag"} <= doc.keys()
