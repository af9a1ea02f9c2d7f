"""The integrator seam: a scheme is an object with ``init`` and ``equations``, and every
stepper runs any scheme. Backward Euler, the second scheme, is checked against its own
recurrence and its order on the unit oscillator x'' + x = 0."""

import dataclasses

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from bristlecrawler import fe
from bristlecrawler.errors import InputError
from bristlecrawler.verification.cases import oscillator

X0 = 1e-2  # mm: the spring stays linear (|x| << its rest length)


def _x(state) -> float:
    return float(state.u[1, 0])


def _run(m, ig, dt: float, n: int) -> np.ndarray:
    step = fe.make_step(m.topology, m.terms, ig)
    s = fe.initial_state(m, q=jnp.asarray([X0]))
    xs = [_x(s)]
    for _ in range(n):
        s, info = step(s, m.params, jnp.asarray(dt))
        assert int(info.status) == 0
        xs.append(_x(s))
    return np.asarray(xs)


def test_backward_euler_follows_its_recurrence_and_damps_as_it_should():
    """(1 + Omega^2) x_{n+1} = 2 x_n - x_{n-1} with x_{-1} = x_0 - dt v_0: the scheme's
    discrete solution, whose roots have modulus 1 / sqrt(1 + Omega^2) (L-stable)."""
    m = oscillator()
    ig = fe.Integrator.backward_euler(tolerance=1e-13)
    for dt in (0.3, 2.0):
        xs = _run(m, ig, dt, 30)
        ref = [X0, X0]  # x_{-1}, x_0 (at rest)
        for _ in range(30):
            ref.append((2.0 * ref[-1] - ref[-2]) / (1.0 + dt**2))
        np.testing.assert_allclose(xs, ref[1:], rtol=1e-9, atol=1e-15)
        # the amplitude decays by the roots' modulus per step
        rho = 1.0 / np.sqrt(1.0 + dt**2)
        assert abs(xs[-1]) <= 2.0 * X0 * rho**30


def test_backward_euler_is_first_order_and_hht_second():
    """Error at t = 2 s against x0 cos t, halving dt: orders 1 and 2."""
    m = oscillator()
    schemes = {
        1.0: fe.Integrator.backward_euler(tolerance=1e-13),
        2.0: fe.Integrator.hht(-0.05, tolerance=1e-13),
    }
    for order, ig in schemes.items():
        errs = []
        for n in (20, 40, 80):
            xs = _run(m, ig, 2.0 / n, n)
            errs.append(abs(xs[-1] - X0 * np.cos(2.0)))
        observed = np.log2(np.asarray(errs[:-1]) / np.asarray(errs[1:]))
        np.testing.assert_allclose(observed, order, atol=0.1)


def _tip(state, params):
    """The mass's position (mm) and the time (s) of each accepted step."""
    return {"x": state.u[1, 0], "t": state.t}


@pytest.mark.parametrize("loop", ["host", "compiled", "batch"])
def test_every_loop_runs_a_scheme_without_a_start(loop):
    """Backward Euler's ``init`` is empty: each loop of the stepper, the batched one too
    (which keeps each design's start while its step is pending), takes it as it takes
    HHT, and the steps of a whole host run (:func:`fe.solve`)."""
    m = oscillator()
    ig = fe.Integrator.backward_euler(tolerance=1e-12)
    s0 = fe.initial_state(m, q=jnp.asarray([X0]))
    save = fe.SaveAt(_tip, 64)
    ref = fe.solve(m, s0, 3.0, 0.25, integrator=ig, save=save)
    stepper = fe.Stepper.of(m, integrator=ig, save=save, loop=loop)
    if loop == "batch":
        params = fe.stack([m.params, m.params])
        carry = stepper.start([s0, s0], [0.25, 0.25], params)
        v = jnp.asarray
        out = stepper.run(carry, params, v([3.0, 3.0]), v([2.5e-5] * 2), v([0.25] * 2))
        buf, k = jax.tree.map(lambda b: np.asarray(b[1]), out.records), int(out.n[1])
        assert int(out.n[0]) == k and not np.any(out.failed)
    else:
        _, buf, k, failed = stepper.run(stepper.start(s0, 0.25), m.params, 3.0, 2.5e-5, 0.25)
        assert not bool(failed)
    assert ref.ok and k == ref.steps > 0
    np.testing.assert_allclose(buf["t"][:k], ref.times, rtol=1e-12)
    np.testing.assert_allclose(buf["x"][:k], ref.records["x"], rtol=1e-9, atol=1e-15)


def test_a_scheme_is_an_object_with_its_settings():
    """The schemes are values (hashable, equal by settings), the base class is abstract,
    and the shared settings are checked whatever the scheme."""
    assert fe.Integrator.backward_euler(tolerance=1e-10) == fe.Integrator.backward_euler(
        tolerance=1e-10
    )
    assert fe.Integrator.backward_euler() != fe.Integrator.newmark()
    assert hash(fe.Integrator.hht()) == hash(fe.Integrator.hht())
    assert isinstance(fe.Integrator.hht(), fe.HHT)
    with pytest.raises(TypeError):
        fe.Integrator()
    with pytest.raises(InputError, match="max_rotation"):
        fe.Integrator.backward_euler(max_rotation=0.0)


def test_schemes_are_made_by_name_and_hht_keeps_its_coefficients_together():
    assert fe.Integrator.of("hht", alpha=-0.1) == fe.Integrator.hht(-0.1)
    assert fe.Integrator.of("backward_euler", tolerance=1e-10) == fe.Integrator.backward_euler(
        tolerance=1e-10
    )
    with pytest.raises(InputError, match="no time scheme named 'rk4'"):
        fe.Integrator.of("rk4")
    # alpha alone would keep alpha = -0.05's beta and gamma: not HHT-alpha
    with pytest.raises(InputError, match=r"Integrator\.hht"):
        dataclasses.replace(fe.Integrator.hht(), alpha=-0.2)
    assert dataclasses.replace(fe.Integrator.hht(), max_rotation=0.5).max_rotation == 0.5


def _position(state, params):
    return state.u[1, 0]


def test_the_stepper_refuses_what_it_cannot_run_in_one_line():
    m = oscillator()
    s0 = fe.initial_state(m, q=jnp.asarray([X0]))
    with pytest.raises(InputError, match="'t' entry"):
        fe.solve(m, s0, 1.0, 0.25, save=fe.SaveAt(_position))
    batch = fe.Stepper.of(m, loop="batch")
    with pytest.raises(InputError, match="params"):
        batch.start([s0, s0], 0.25)
    with pytest.raises(InputError, match="one design"):
        batch.solve(s0, m.params, 1.0, 0.25)
    with pytest.raises(InputError, match="loop"):
        fe.Stepper.of(m, loop="gpu")
