"""A converged step whose contact penetration exceeds ``Integrator.penetration_limit`` is
rejected (status PENETRATION) and cut by the adaptive driver; below the limit nothing
changes. A mass on a flat substrate under a load F settles at the penalty's depth F / k_n."""

import math

import jax.numpy as jnp
import numpy as np
import pytest

from bristlecrawler import fe
from bristlecrawler.contact import CoulombLaw, Flat
from bristlecrawler.contact.term import SubstrateContact
from bristlecrawler.errors import InputError, SolverError
from bristlecrawler.fe.status import PENETRATION

F = 2.0  # N, pressing load
K_N = 1e3  # N/mm: the equilibrium depth F / k_n is 2e-3 mm


def _pressed_mass():
    s = fe.Structure()
    n = s.node(0.0, 0.0)
    s.rigid_body(n, 1e-6, 1e-6)  # t, t mm^2
    s.fix(n, ("x", "theta"))
    s.load(n, fy=-F)
    term = SubstrateContact((n,))
    s.add_term(
        term,
        SubstrateContact.params(
            np.zeros((1, 3)), (n,), Flat(), CoulombLaw(mu=0.0, k_n=K_N, k_t=K_N)
        ),
    )
    s.damping(2e3, 0.0)
    m = s.build()
    return m, fe.initial_state(m)


@pytest.mark.slow
@pytest.mark.parametrize("limit", [math.inf, 4e-3])
def test_steps_below_the_limit_are_accepted(limit):
    m, s0 = _pressed_mass()
    ig = fe.Integrator.hht(penetration_limit=limit)
    res = fe.solve(m, s0, 0.05, 1e-3, integrator=ig)
    depth = -float(res.state.u[0, 1])
    assert res.ok and depth == pytest.approx(F / K_N, rel=0.05)
    hist = res.state.history[0]
    assert float(m.terms[0].penetration(hist, m.params.extra[0])) == pytest.approx(depth, rel=1e-6)


@pytest.mark.slow
def test_a_step_deeper_than_the_limit_is_rejected():
    m, s0 = _pressed_mass()
    ig = fe.Integrator.hht(penetration_limit=1e-3)  # half the equilibrium depth
    step = fe.make_step(m.topology, m.terms, ig)
    state, info = s0, None
    for _ in range(200):
        new, info = step(state, m.params, jnp.asarray(1e-3))
        if int(info.status) != 0:
            break
        state = new
    assert int(info.status) == PENETRATION
    assert -float(state.u[0, 1]) <= 1e-3  # the last accepted state is within the limit
    with pytest.raises(SolverError, match="penetration"):
        fe.solve(m, s0, 0.05, 1e-3, integrator=ig)


def test_limit_must_be_positive():
    with pytest.raises(InputError, match="penetration_limit"):
        fe.Integrator.hht(penetration_limit=0.0)
