"""Newton's line search: the monotone option converges where full corrections cycle."""

import math

import jax.numpy as jnp
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from bristlecrawler.errors import InputError
from bristlecrawler.fe import Integrator
from bristlecrawler.fe.newton import NewtonOptions
from bristlecrawler.fe.newton import newton as _newton
from bristlecrawler.fe.status import MAX_ITERATIONS, STALLED, SUCCESS
from bristlecrawler.verification.cases import cantilever


def newton(residual, q0, topo, predict=None, monotone=False, max_move=math.inf, **kw):
    """:func:`fe.newton.newton` with its options given as keywords."""
    line_search = "monotone" if monotone else "growth"
    opts = NewtonOptions(line_search=line_search, max_correction=max_move, **kw)
    return _newton(residual, q0, topo, opts, predict=predict)


def _solve(monotone, target):
    """R(q) = arctan(q - target) per DOF (a diagonal, banded Jacobian): full Newton steps
    from 0 overshoot and grow for |target| > 1.39 (the classic arctan example)."""
    topo = cantilever().topology

    def residual(q):
        return jnp.arctan(q - target), jnp.asarray(1.0)

    q0 = jnp.zeros(topo.n_red)
    return newton(
        residual, q0, topo, tolerance=1e-12, atol=0.0, max_iterations=40, monotone=monotone
    )


@pytest.mark.parametrize("target", [1.5, 2.0, 3.0])
def test_monotone_line_search_converges_where_full_steps_diverge(target):
    # Full corrections run away (|q| ~ 1e170-1e290 within 9-11 iterations): reported as a
    # failure, not as a stalled (converged) iterate.
    assert int(_solve(False, target)[4]) != SUCCESS
    q, _, _, _, status = _solve(True, target)
    assert int(status) == SUCCESS
    np.testing.assert_allclose(np.asarray(q), target, atol=1e-10)


@pytest.mark.slow
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
    return newton(
        residual, q, topo, tolerance=1e-12, atol=0.0, max_iterations=40, stall_iterations=stall
    )


@pytest.mark.slow
def test_stall_stops_newton_early_with_its_own_status():
    _, it, _, _, status = _rootless(0)
    assert int(status) == MAX_ITERATIONS and int(it) == 40
    _, it, _, _, status = _rootless(4)
    assert int(status) == STALLED
    assert 4 <= int(it) < 40


@pytest.mark.slow
def test_stall_leaves_a_converging_newton_alone():
    """Quadratic convergence halves the residual every iteration: the same iterates."""
    topo = cantilever().topology

    def residual(q):
        return jnp.arctan(q - 0.5), jnp.asarray(1.0)

    q0 = jnp.zeros(topo.n_red)
    a = newton(residual, q0, topo, tolerance=1e-12, atol=0.0, max_iterations=40)
    b = newton(residual, q0, topo, tolerance=1e-12, atol=0.0, max_iterations=40, stall_iterations=2)
    assert int(a[4]) == int(b[4]) == SUCCESS
    assert int(a[1]) == int(b[1])
    np.testing.assert_array_equal(np.asarray(a[0]), np.asarray(b[0]))


def test_max_iter_below_one_is_refused():
    """With no iteration allowed the result would be the start's, reported as solved
    from a placeholder residual: refused before any work."""
    topo = cantilever().topology
    q0 = jnp.full(topo.n_red, 5.0)
    for bad in (0, -1, 2.5):
        with pytest.raises(InputError, match="max_iter"):
            newton(
                _drifting,
                q0,
                topo,
                predict=(0.0, 1.0, 1.0),
                tolerance=1e-9,
                atol=0.0,
                max_iterations=bad,
            )


def test_negative_stall_is_refused():
    with pytest.raises(InputError, match="stall"):
        Integrator.hht(stall_iterations=-1)


def _drifting(q, tc, c=1.2):
    """R(q, t) = arctan(q - c t) per DOF: the root moves with t (c mm/s), and the tangent
    predictor from a root at t0, J dq = -(R + dR/dt dt), lands on the root at t1."""
    return jnp.arctan(q - c * tc), jnp.asarray(1.0)


@pytest.mark.slow
def test_timed_extraction_gives_the_time_derivative_of_the_same_linearisation():
    import jax

    from bristlecrawler.fe import banded

    topo = cantilever().topology
    q = jnp.linspace(-1.0, 2.0, topo.n_red)
    t, dt = jnp.asarray(0.3), jnp.asarray(0.7)
    y, J, yt = banded.extract(lambda q, tc: _drifting(q, tc)[0], q, topo, t, dt)
    y0, ref = jax.jvp(lambda tc: _drifting(q, tc)[0], (t,), (dt,))
    np.testing.assert_allclose(np.asarray(y), np.asarray(y0), rtol=1e-15)
    np.testing.assert_allclose(np.asarray(yt), np.asarray(ref), rtol=1e-14)
    dense = banded.to_scipy(J, topo).toarray()
    np.testing.assert_allclose(np.diag(dense), 1.0 / (1.0 + (q - 1.2 * t) ** 2), rtol=1e-14)
    np.testing.assert_allclose(dense - np.diag(np.diag(dense)), 0.0, atol=0.0)
    _, J0 = banded.extract(lambda q: _drifting(q, t)[0], q, topo)
    np.testing.assert_array_equal(banded.to_scipy(J0, topo).toarray(), dense)


@pytest.mark.slow
def test_predictor_is_newtons_first_iteration():
    """From the root at t0 the predictor alone solves the drifting arctan at t1 (one
    iteration, no correction); plain Newton from the same start needs several."""
    topo = cantilever().topology
    t0, t1 = jnp.asarray(0.0), jnp.asarray(1.0)
    q0 = jnp.zeros(topo.n_red)  # root at t0
    kw = dict(tolerance=1e-12, atol=0.0, max_iterations=40)
    q, it, _, _, status = newton(_drifting, q0, topo, predict=(t0, t1, t1 - t0), **kw)
    assert int(status) == SUCCESS and int(it) == 1
    np.testing.assert_allclose(np.asarray(q), 1.2, rtol=1e-14)
    q, it, _, _, status = newton(lambda q: _drifting(q, t1), q0, topo, **kw)
    assert int(status) == SUCCESS and int(it) >= 4
    # The predictor counts against max_iter, and is taken even when it is the last one.
    _, it, _, _, status = newton(
        _drifting, q0, topo, predict=(t0, t1, t1 - t0), max_iterations=1, tolerance=1e-12, atol=0.0
    )
    assert int(it) == 1 and int(status) == SUCCESS


def test_predictor_from_a_state_off_the_root_includes_its_residual():
    """A linear residual R = A q - b t (A diagonal, from 1 to 3): from any q0 the predictor
    J dq = -(R(q0, t0) + dR/dt dt) lands exactly on the root at t1, so Newton ends after
    it. The predictor reads R(q0, t0) from its own linearisation (no separate residual
    evaluation): a predictor that missed it would land at q0 + b dt / A instead."""
    topo = cantilever().topology
    a = jnp.linspace(1.0, 3.0, topo.n_red)
    b = 0.8

    def linear(q, tc):
        return a * q - b * tc, jnp.asarray(1.0)

    t0, t1 = jnp.asarray(0.4), jnp.asarray(0.9)
    q0 = jnp.linspace(-0.7, 1.3, topo.n_red)  # far from the root b t0 / a
    q, it, _, _, status = newton(
        linear, q0, topo, predict=(t0, t1, t1 - t0), tolerance=1e-12, atol=0.0, max_iterations=5
    )
    assert int(status) == SUCCESS and int(it) == 1
    np.testing.assert_allclose(np.asarray(q), np.asarray(b * t1 / a), rtol=1e-13)


def _two_laws(q, freeze=False):
    """R(q) = arctan(q - 0.5) per DOF, and with ``freeze`` another law, arctan(q - 2):
    a frozen residual whose root is not the free one's."""
    c = jnp.where(freeze, 2.0, 0.5)
    return jnp.arctan(q - c), jnp.asarray(1.0)


@pytest.mark.slow
def test_frozen_iterations_never_end_newton_on_the_frozen_root():
    topo = cantilever().topology
    q0 = jnp.full(topo.n_red, 1.9)
    kw = dict(tolerance=1e-12, atol=0.0, max_iterations=40, monotone=True)
    q, it, _, _, status = newton(_two_laws, q0, topo, freeze_iterations=6, **kw)
    assert int(status) == SUCCESS
    # The free root, not the frozen one (both are within a monotone Newton's reach).
    np.testing.assert_allclose(np.asarray(q), 0.5, atol=1e-10)
    free = newton(_two_laws, q0, topo, **kw)
    # The frozen phase ends as soon as it has solved its own problem (its root at 2 is
    # 0.1 away: a few iterations), well before the 6 allowed, so the frozen start costs
    # those few iterations and no more.
    assert int(free[1]) < int(it) < int(free[1]) + 6
    # Off, the residual is called without the flag: the same iterates as before.
    np.testing.assert_array_equal(
        np.asarray(free[0]), np.asarray(newton(lambda q: _two_laws(q), q0, topo, **kw)[0])
    )


def test_a_frozen_limit_of_one_iteration_still_converges_on_the_free_law():
    topo = cantilever().topology
    q0 = jnp.zeros(topo.n_red)
    q, _, _, _, status = newton(
        _two_laws,
        q0,
        topo,
        tolerance=1e-12,
        atol=0.0,
        max_iterations=40,
        monotone=True,
        freeze_iterations=1,
    )
    assert int(status) == SUCCESS
    np.testing.assert_allclose(np.asarray(q), 0.5, atol=1e-10)


@pytest.mark.parametrize("freeze", [-1, 12, 13])
def test_freeze_outside_zero_to_max_iterations_is_refused(freeze):
    with pytest.raises(InputError, match="freeze"):
        Integrator.hht(freeze_iterations=freeze, max_iterations=12)


def _linear(topo, translation, rotation):
    """R(q) = q - target per DOF: full Newton solves it in one correction. The target
    moves every translation DOF by ``translation`` mm and every rotation by ``rotation``."""
    is_translation = np.asarray(topo.arrays()["red"])[:, 1] < 2
    target = jnp.asarray(np.where(is_translation, translation, rotation))

    def residual(q):
        return q - target, jnp.asarray(1.0)

    return residual, target


@pytest.mark.slow
@pytest.mark.parametrize(
    ("move", "cap", "expected"), [(1.0, 0.3, 4), (1.0, 0.25, 4), (1.0, 0.1, 10), (0.2, 0.3, 1)]
)
def test_max_move_caps_each_correction_of_the_translations(move, cap, expected):
    """A linear residual: each correction is the whole remaining distance, capped at
    ``cap`` mm of nodal translation, and the monotone search takes every capped trial
    (the residual falls linearly along it). So Newton needs ceil(move / cap) corrections
    and lands on the same root."""
    topo = cantilever().topology
    residual, target = _linear(topo, move, 0.0)
    q0 = jnp.zeros(topo.n_red)
    kw = dict(tolerance=1e-12, atol=0.0, max_iterations=40, monotone=True)
    q, it, _, _, status = newton(residual, q0, topo, max_move=cap, **kw)
    assert int(status) == SUCCESS and int(it) == expected
    np.testing.assert_allclose(np.asarray(q), np.asarray(target), atol=1e-12)
    q, it, _, _, status = newton(residual, q0, topo, **kw)
    assert int(status) == SUCCESS and int(it) == 1


@pytest.mark.slow
def test_max_move_leaves_rotations_alone():
    """Rotations (rad) do not count against the cap (mm): a correction that turns every
    node by 1 rad and moves none is taken whole, as without the cap."""
    topo = cantilever().topology
    residual, target = _linear(topo, 0.0, 1.0)
    q0 = jnp.zeros(topo.n_red)
    kw = dict(tolerance=1e-12, atol=0.0, max_iterations=40, monotone=True)
    a = newton(residual, q0, topo, max_move=0.01, **kw)
    b = newton(residual, q0, topo, **kw)
    assert int(a[4]) == int(b[4]) == SUCCESS
    assert int(a[1]) == int(b[1]) == 1
    np.testing.assert_array_equal(np.asarray(a[0]), np.asarray(b[0]))
    np.testing.assert_allclose(np.asarray(a[0]), np.asarray(target), atol=1e-12)


@pytest.mark.parametrize("cap", [0.0, -1.0, -math.inf, math.nan])
def test_non_positive_max_correction_is_refused(cap):
    with pytest.raises(InputError, match="max_correction"):
        Integrator.hht(max_correction=cap)
    topo = cantilever().topology
    residual, _ = _linear(topo, 1.0, 0.0)
    with pytest.raises(InputError, match="max_correction"):
        newton(
            residual,
            jnp.zeros(topo.n_red),
            topo,
            tolerance=1e-12,
            atol=0.0,
            max_iterations=4,
            max_move=cap,
        )


@pytest.mark.slow
def test_the_dynamic_step_caps_its_corrections():
    """`Integrator.max_correction` reaches the step's Newton: a cantilever under a sudden
    tip load, one long HHT step from rest, Newton from the last state (constant
    predictor). Each correction moves the tip by at most the cap, so Newton needs at least
    |u_tip| / cap iterations, and the step converges to the same state."""
    import jax

    from bristlecrawler.fe import Structure, initial_state, make_step
    from bristlecrawler.verification.structures import PAPER_BRISTLE

    s = Structure()
    root = s.node(0.0, 0.0)
    tip = s.chain(root, (5.0, 0.0), 8, PAPER_BRISTLE)[-1]
    s.fix(root)
    s.load(tip, fy=-0.05)
    m = s.build()
    state = initial_state(m)
    runs = {}
    for cap in (math.inf, 0.01):
        ig = Integrator.hht(predictor="constant", max_iterations=100, max_correction=cap)
        new, info = make_step(m.topology, m.terms, ig)(state, m.params, jnp.asarray(1.0))
        assert int(info.status) == SUCCESS
        runs[cap] = (jax.device_get(new.u), int(info.iterations))
    (u_free, it_free), (u_cap, it_cap) = runs[math.inf], runs[0.01]
    deflection = abs(float(u_free[tip, 1]))
    assert deflection > 0.1  # far beyond the cap: the test can tell
    assert it_free < deflection / 0.01 <= it_cap
    np.testing.assert_allclose(u_cap, u_free, rtol=0.0, atol=1e-8 * deflection)


@pytest.mark.slow
@settings(max_examples=8, deadline=None)
@given(
    target=st.floats(-4.0, 4.0),
    monotone=st.booleans(),
    cap=st.sampled_from([math.inf, 0.3]),
    wall=st.sampled_from([math.inf, 2.5]),
)
def test_parallel_trials_give_the_sequential_line_search(target, monotone, cap, wall):
    """Making every trial of the line search at once selects the trial the sequential
    search stops at: the same iterates, iterations and status, bit for bit, with
    backtracking (arctan overshoot), capped corrections and non-finite trials (NaN
    beyond |q| = ``wall``)."""
    topo = cantilever().topology

    def residual(q):
        r = jnp.arctan(q - target)
        return jnp.where(jnp.abs(q) > wall, jnp.nan, r), jnp.asarray(1.0)

    q0 = jnp.zeros(topo.n_red)
    line_search = "monotone" if monotone else "growth"
    opts = NewtonOptions(
        line_search=line_search, max_correction=cap, tolerance=1e-12, max_iterations=30
    )
    seq, par = (_newton(residual, q0, topo, opts, parallel=p) for p in (False, True))
    np.testing.assert_array_equal(np.asarray(seq[0]), np.asarray(par[0]))
    assert [int(x) for x in (seq[1], seq[4])] == [int(x) for x in (par[1], par[4])]
