"""A converged dynamic step that turns a node by more than ``Integrator.max_rotation`` is
rejected (status ROTATION_LIMIT) and the adaptive driver cuts it: rotations enter the
energy only modulo 2 pi, so an over-long step can converge to a node turned by ~2 pi."""

import itertools

import jax.numpy as jnp
import pytest

from bristlecrawler import fe
from bristlecrawler.errors import InputError
from bristlecrawler.fe.status import ROTATION_LIMIT
from bristlecrawler.verification.cases import N_ELEM, cantilever


def _rotations(state, params):
    return {"t": state.t, "theta": state.u[:, 2]}


@pytest.fixture(scope="module")
def twisted():
    """The verification cantilever under a suddenly applied end moment (tip turns ~0.3 rad)."""
    m = cantilever(N_ELEM)
    EI = float(m.params.sec[0, 0] * m.params.sec[0, 2] * m.params.sec[0, 3] ** 3 / 12.0)
    L = float(jnp.max(m.params.X[:, 0]) - jnp.min(m.params.X[:, 0]))
    m = m.with_params(load_vec=jnp.asarray([[0.0, 0.0, 0.3 * EI / L]]))
    return m, fe.initial_state(m)


@pytest.mark.slow
def test_a_step_that_turns_a_node_too_far_is_rejected(twisted):
    m, s0 = twisted
    big = fe.Integrator.hht(max_rotation=1e-3)
    step = fe.make_step(m.topology, m.terms, big)
    new, info = step(s0, m.params, jnp.asarray(50.0))
    assert int(info.status) == ROTATION_LIMIT
    assert float(jnp.max(jnp.abs(new.u[:, 2]))) == 0.0  # state handed back unchanged
    # The same step with the default limit is accepted, and turns the tip by more than 1e-3.
    new, info = fe.make_step(m.topology, m.terms, fe.Integrator.hht())(s0, m.params, 50.0)
    assert int(info.status) == 0 and float(jnp.max(jnp.abs(new.u[:, 2]))) > 1e-3


@pytest.mark.slow
def test_the_driver_cuts_until_each_step_turns_less(twisted):
    m, s0 = twisted
    res = fe.solve(
        m,
        s0,
        50.0,
        50.0,
        integrator=fe.Integrator.hht(max_rotation=0.02),
        dt_min=1e-3,
        save=fe.SaveAt(_rotations),
    )
    assert res.ok and res.rejected >= 1
    rot = [0.0] + [float(jnp.max(jnp.abs(o))) for o in res.records["theta"]]
    assert max(abs(b - a) for a, b in itertools.pairwise(rot)) <= 0.02


def test_limit_must_be_positive():
    with pytest.raises(InputError, match="max_rotation"):
        fe.Integrator.hht(max_rotation=-1.0)
