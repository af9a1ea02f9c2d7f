"""Backward Euler: first order, L-stable; for runs where inertia is a regulariser.

    M a1 + r(u1, v1, t1) = 0,   v1 = (u1 - u0) / dt,   a1 = (v1 - v0) / dt,
    r = C v + f_int(u) + sum_k r_k(u, v, t, h_k) - f_ext(t).

Every mode is damped, the more the larger omega dt (amplification 1 / (1 + omega^2 dt^2)
per step for an undamped oscillator, against 1 for the trapezoidal rule): with steps long
against the structure's periods it settles each step near equilibrium, the form of a
quasi-static run whose snaps release their energy instead of ringing. Its error is first
order in dt (HHT's is second). Constraints as in :mod:`.hht`: imposed at t1 through
u1 = expand(q1, t1), the residual projected by the expansion's transpose.
"""

from __future__ import annotations

import dataclasses

import jax
import jax.numpy as jnp

from bristlecrawler.fe import assembly
from bristlecrawler.fe.integrator import Integrator, element_masses, force


@dataclasses.dataclass(frozen=True, init=False)
class BackwardEuler(Integrator, scheme="backward_euler"):
    """Backward Euler (make it with :meth:`Integrator.backward_euler`). Nothing is shared
    between the steps from one state but the state itself (:meth:`init` is empty)."""

    def init(self, state, params, topo, terms):
        return ()

    def equations(self, state, start, params, dt, topo, terms):
        t1 = state.t + dt
        u0, v0 = state.u, state.v
        Me = element_masses(params, topo)

        def euler(u):
            v = (u - u0) / dt
            return u, v, (v - v0) / dt

        def kin(q, tc=t1):
            return euler(assembly.expand(q, tc, 1.0, params, topo))

        def residual(q, tc=t1, freeze=False):
            u, pull = jax.vjp(lambda q: assembly.expand(q, tc, 1.0, params, topo), q)
            u, v, a = euler(u)
            r1, s1 = force(u, v, t1, state.history, params, topo, terms, freeze, Me)
            Ma = assembly.mass_times(a, params, topo, Me)
            (R,) = pull(Ma + r1)
            return R, jnp.linalg.norm(Ma) + s1

        return kin, residual
