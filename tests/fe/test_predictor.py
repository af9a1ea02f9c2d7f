"""The tangent predictor of the dynamic step: a finely meshed bristle carried by a moving
support (the crawler's actuated body end) is translated, not rotated, by the first solve.

From the last converged state, a support shift delta distorts the stiff first element
(12 EI / l^3 ~ 1e6 N/mm here); the residual of that distortion has a second-order part of
relative size delta / l that the soft bending modes of the whole bristle amplify, so full
Newton from the old configuration diverges after a few um of motion per step (the defect of
the 200-element benchmark run). The tangent predictor linearises the residual in the support
motion instead, and a rigid translation is the answer of that linear problem.
"""

import math

import jax.numpy as jnp
import numpy as np
import pytest

from bristlecrawler.fe import Integrator, Stepper, Structure, initial_state, solve_static
from bristlecrawler.fe.motion import SmoothRamp
from bristlecrawler.verification.structures import PAPER_BRISTLE

N_ELEM = 60
SPEED = 2.0  # mm/s, about the crawler's peak stroke speed (pi s~ / T = 3.1 mm/s)
DT = 1e-3  # s
STEPS = 60


def _carried_bristle():
    """A paper bristle at 45 degrees clamped to a support node moving along x."""
    s = Structure()
    root = s.node(0.0, 0.0)
    d = (5.0 * math.sin(math.pi / 4), -5.0 * math.cos(math.pi / 4))
    chain = s.chain(root, d, N_ELEM, PAPER_BRISTLE)
    # Velocity blended in over 5 ms, then constant: SPEED over most of the run.
    dur = 10.0
    s.prescribe(root, "x", SmoothRamp(SPEED * (dur - 0.005), dur, 0.005))
    s.prescribe(root, "y", 0.0)
    s.prescribe(root, "theta", 0.0)
    return s.build(), chain


@pytest.fixture(scope="module")
def carried():
    m, chain = _carried_bristle()
    return m, chain, initial_state(m)


def _run(carried, predictor):
    m, _chain, s0 = carried
    ig = Integrator.hht(predictor=predictor, max_iterations=8)
    return Stepper.of(m, integrator=ig).fixed(s0, m.params, DT, STEPS)


@pytest.mark.slow
def test_tangent_predictor_carries_the_bristle(carried):
    _m, chain, _ = carried
    final, infos = _run(carried, "tangent")
    assert np.all(np.asarray(infos.status) == 0)
    # At constant support speed (after the 5 ms blend): the predictor (counted as one
    # iteration) plus at most two corrections per step.
    assert int(np.max(np.asarray(infos.iterations)[10:])) <= 3
    # No gravity, no load: the bristle follows its root as a rigid body (to the inertial
    # bending of a bristle accelerated over 5 ms, far below the um the root moves per step).
    u = np.asarray(final.u)
    np.testing.assert_allclose(u[chain, 0], u[chain[0], 0], rtol=0, atol=2e-5)
    np.testing.assert_allclose(u[chain, 1:], 0.0, atol=2e-5)
    assert u[chain[0], 0] > 0.5 * SPEED * STEPS * DT


@pytest.mark.slow
def test_constant_predictor_diverges_there(carried):
    """The same steps from the last converged q (the previous predictor) do not converge:
    the case above is one a predictor can fail."""
    _, infos = _run(carried, "constant")
    assert np.any(np.asarray(infos.status) != 0)


def test_predictor_name_is_checked():
    from bristlecrawler.errors import InputError

    with pytest.raises(InputError, match="predictor"):
        Integrator.hht(predictor="linear")


@pytest.mark.slow
def test_free_oscillation_is_unchanged_by_the_predictor():
    """With nothing prescribed in motion the predictor is the first Newton correction: both
    predictors converge to the same steps of a released cantilever."""
    from bristlecrawler.verification.cases import N_ELEM as N
    from bristlecrawler.verification.cases import cantilever

    m = cantilever(N)
    EI = float(m.params.sec[0, 0] * m.params.sec[0, 2] * m.params.sec[0, 3] ** 3 / 12.0)
    pre = m.with_params(load_vec=jnp.asarray([[0.0, 1e-3 * EI, 0.0]]))
    m = m.with_params(load_vec=jnp.asarray([[0.0, 0.0, 0.0]]))
    s0 = initial_state(m, q=solve_static(pre, check_support=False).state.q)
    out = []
    for pred in ("tangent", "constant"):
        stepper = Stepper.of(m, integrator=Integrator.hht(predictor=pred))
        fin, infos = stepper.fixed(s0, m.params, 5.0, 20)
        assert np.all(np.asarray(infos.status) == 0)
        out.append(np.asarray(fin.u))
    np.testing.assert_allclose(out[0], out[1], rtol=0, atol=1e-9 * np.abs(out[1]).max())
