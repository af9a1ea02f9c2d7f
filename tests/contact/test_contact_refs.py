"""Analytic references of the contact verification cases, cross-checked independently."""

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from bristlecrawler.errors import InputError
from bristlecrawler.verification.contact_refs import (
    OscillatorParams,
    cantilever_drag,
    coulomb_oscillator,
    coulomb_oscillator_position,
    incline_push_ratio,
    inclined_cantilever_compliance,
    integrate_coulomb_oscillator,
)


def test_oscillator_case_of_the_brief():
    # 1 kg = 1e-3 t, 100 N/m = 0.1 N/mm, g = 9810 mm/s^2: omega = 10 rad/s,
    # stick band mu m g / k = 9.81 mm, amplitude drop per half cycle 19.62 mm.
    h = coulomb_oscillator()
    np.testing.assert_allclose(h.positions, [100, -80.38, 60.76, -41.14, 21.52, -1.90], atol=1e-9)
    assert h.stop_time == pytest.approx(5 * math.pi / 10)
    ref = integrate_coulomb_oscillator()
    np.testing.assert_allclose(ref.positions, h.positions, atol=1e-7)
    np.testing.assert_allclose(ref.times, h.times, atol=1e-9)
    assert ref.stop_time == pytest.approx(h.stop_time, abs=1e-9)


@given(mu=st.floats(0.02, 0.5), x0=st.floats(-200, 200), k=st.floats(0.01, 1.0))
def test_oscillator_closed_form_matches_integrator(mu, x0, k):
    p = OscillatorParams(stiffness=k, mu=mu, x0=x0)
    h, ref = coulomb_oscillator(p), integrate_coulomb_oscillator(p, t_end=1e3)
    assert len(ref.positions) == len(h.positions)
    np.testing.assert_allclose(ref.positions, h.positions, atol=1e-6 * (1 + abs(x0)))
    assert ref.stop_time == pytest.approx(h.stop_time, rel=1e-8, abs=1e-9)
    assert abs(h.positions[-1]) <= p.stick_band  # stops inside the stick band
    assert np.all(np.abs(h.positions[:-1]) > p.stick_band)


def test_oscillator_position_is_continuous_with_zero_velocity_at_turning_points():
    h = coulomb_oscillator()
    for t in h.times[1:]:
        xs = coulomb_oscillator_position(np.array([t - 1e-7, t, t + 1e-7]))
        assert xs[0] == pytest.approx(xs[1], abs=1e-9)
        assert xs[2] == pytest.approx(xs[1], abs=1e-9)
    # energy is only lost: spring energy at the turning points decreases
    e = 0.5 * 0.1 * h.positions**2
    assert np.all(np.diff(e) < 0)


def test_incline_push_ratio_matches_force_balance():
    r = incline_push_ratio(0.1, 0.3)
    assert r == pytest.approx(0.4 / 0.97)
    # independent: solve the 2x2 equilibrium for push P and normal N (weight 1)
    a = math.atan(0.1)
    m = np.array([[math.cos(a), -0.3], [math.sin(a), -1.0]])
    rhs = np.array([math.sin(a), -math.cos(a)])
    p, n = np.linalg.solve(m, rhs)
    assert r == pytest.approx(p, rel=1e-12) and n > 0
    with pytest.raises(InputError, match="self-locks"):
        incline_push_ratio(2.0, 0.6)


def test_vertical_cantilever_drag_is_symmetric():
    c = inclined_cantilever_compliance(5.0, 10.0, 100.0, 0.0)
    right, left = cantilever_drag(c, 0.01, 0.65, 1), cantilever_drag(c, 0.01, 0.65, -1)
    k = np.linalg.inv(c)
    assert right.drag_at_slip == pytest.approx(0.01 * 0.65 * k[1, 1] / k[0, 0])
    assert left.drag_at_slip == pytest.approx(right.drag_at_slip)
    assert right.friction_in_slip == pytest.approx(0.65 * right.normal_in_slip)
    assert right.normal_in_slip == pytest.approx(right.normal_at_press)


def test_inclined_stiff_cantilever_is_directional():
    # Nearly inextensible beam leaning at 22.5 deg < atan(0.65): dragging it "against the
    # lean" wedges the tip, dragging the other way slides.
    c = inclined_cantilever_compliance(5.0, 10.0, 1e4, math.pi / 8)
    assert cantilever_drag(c, 0.01, 0.65, 1).self_locks
    assert not cantilever_drag(c, 0.01, 0.65, -1).self_locks
