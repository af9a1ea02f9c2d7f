"""Newton's line search: the monotone option converges where full corrections cycle."""

import jax.numpy as jnp
import numpy as np
import pytest

from bristlecrawler.errors import InputError
from bristlecrawler.fe import Integrator
from bristlecrawler.fe.newton import newton
from bristlecrawler.fe.status import MAX_ITERATIONS, STALLED, SUCCESS
from bristlecrawler.verification.cases import cantilever


def _solve(monotone, target):
    """R(q) = arctan(q - target) per DOF (a diagonal, banded Jacobian): full Newton steps
    from 0 overshoot and grow for |target| > 1.39 (the classic arctan example)."""
    topo = cantilever().topology

    def residual(q):
        return jnp.arctan(q - target), jnp.asarray(1.0)

    q0 = jnp.zeros(topo.n_red)
    return newton(residual, q0, topo, rtol=1e-12, atol=0.0, max_iter=40, monotone=monotone)


@pytest.mark.parametrize("target", [1.5, 2.0, 3.0])
def test_monotone_line_search_converges_where_full_steps_diverge(target):
    # Full corrections run away (|q| ~ 1e170-1e290 within 9-11 iterations): reported as a
    # failure, not as a stalled (converged) iterate.
    assert int(_solve(False, target)[4]) != SUCCESS
    q, _, _, _, status = _solve(True, target)
    assert int(status) == SUCCESS
    np.testing.assert_allclose(np.asarray(q), target, atol=1e-10)


def test_monotone_line_search_keeps_full_steps_near_the_root():
    """Where full Newton converges, the monotone search takes the same (full) steps."""
    a = _solve(False, 0.5)
    b = _solve(True, 0.5)
    assert int(a[4]) == int(b[4]) == SUCCESS
    assert int(a[1]) == int(b[1])
    np.testing.assert_array_equal(np.asarray(a[0]), np.asarray(b[0]))


def test_unknown_line_search_is_refused():
    with pytest.raises(InputError, match="line_search"):
        Integrator.hht(line_search="wolfe")


def _rootless(stall, q0=0.5):
    """R(q) = q^2 + 1 per DOF has no real root: Newton's map q -> (q^2 - 1) / (2 q) wanders
    (chaotically) and the residual never settles into halving."""
    topo = cantilever().topology

    def residual(q):
        return q**2 + 1.0, jnp.asarray(1.0)

    q = jnp.full(topo.n_red, q0)
    return newton(residual, q, topo, rtol=1e-12, atol=0.0, max_iter=40, stall=stall)


def test_stall_stops_newton_early_with_its_own_status():
    _, it, _, _, status = _rootless(0)
    assert int(status) == MAX_ITERATIONS and int(it) == 40
    _, it, _, _, status = _rootless(4)
    assert int(status) == STALLED
    assert 4 <= int(it) < 40


def test_stall_leaves_a_converging_newton_alone():
    """Quadratic convergence halves the residual every iteration: the same iterates."""
    topo = cantilever().topology

    def residual(q):
        return jnp.arctan(q - 0.5), jnp.asarray(1.0)

    q0 = jnp.zeros(topo.n_red)
    a = newton(residual, q0, topo, rtol=1e-12, atol=0.0, max_iter=40)
    b = newton(residual, q0, topo, rtol=1e-12, atol=0.0, max_iter=40, stall=2)
    assert int(a[4]) == int(b[4]) == SUCCESS
    assert int(a[1]) == int(b[1])
    np.testing.assert_array_equal(np.asarray(a[0]), np.asarray(b[0]))


def test_negative_stall_is_refused():
    with pytest.raises(InputError, match="stall"):
        Integrator.hht(stall=-1)
