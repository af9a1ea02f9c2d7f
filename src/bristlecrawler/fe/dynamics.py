"""Implicit dynamics: the time step of any :class:`~.integrator.Integrator` (HHT-alpha and
Newmark in :mod:`.hht`, backward Euler in :mod:`.backward_euler`), Rayleigh damping, the
consistent initial state.

A step solves the integrator's equations (:meth:`Integrator.equations`) for the reduced
unknowns with Newton (:mod:`.newton`), then commits the terms' histories and checks the
converged state (rotation, penetration, broad-phase overflow, damping). Rayleigh damping
C v = a0 M v + a1 K_T(u) v, with K_T v a JVP of the internal force (left out of the
programs of a topology built without stiffness damping,
:func:`assembly.internal_and_damping_force`).
"""

from __future__ import annotations

import dataclasses
import functools
import math
from typing import Any

import jax
import jax.numpy as jnp

from bristlecrawler._pytree import pytree
from bristlecrawler.errors import InputError
from bristlecrawler.fe import assembly, banded
from bristlecrawler.fe.integrator import Integrator, force
from bristlecrawler.fe.newton import newton_parts
from bristlecrawler.fe.programs import stored
from bristlecrawler.fe.status import (
    PENETRATION,
    ROTATION_LIMIT,
    SUCCESS,
    UNSUPPORTED_DAMPING,
    StepInfo,
)
from bristlecrawler.fe.terms import (
    commit_all,
    flag_overflow,
    init_histories,
    max_penetration,
)


@pytree()
class DynState:
    """t (s); q reduced unknowns; u, v, a full nodal displacement (mm, rad), velocity
    (mm/s, rad/s), acceleration (mm/s^2, rad/s^2), shape (n_nodes, 3); history of terms."""

    t: Any
    q: Any
    u: Any
    v: Any
    a: Any
    history: tuple


@dataclasses.dataclass(frozen=True)
class Rayleigh:
    """Rayleigh damping C = a0 M + a1 K: a0 (1/s), a1 (s)."""

    a0: float = 0.0
    a1: float = 0.0

    @classmethod
    def from_ratio(cls, zeta: float, omega: float, kind: str = "mass") -> Rayleigh:
        """Damping ratio ``zeta`` at circular frequency ``omega`` (rad/s).

        kind 'mass' (a0 = 2 zeta omega, the paper's choice), 'stiffness' (a1 = 2 zeta/omega)
        or 'both' (each half: zeta(omega) = a0/(2 omega) + a1 omega/2 = zeta).
        """
        if not (zeta >= 0.0 and omega > 0.0):
            raise InputError(f"Rayleigh needs zeta >= 0 and omega > 0, got {zeta}, {omega}")
        if kind == "mass":
            return cls(2.0 * zeta * omega, 0.0)
        if kind == "stiffness":
            return cls(0.0, 2.0 * zeta / omega)
        if kind == "both":
            return cls(zeta * omega, zeta / omega)
        raise InputError(f"Rayleigh kind must be mass, stiffness or both, got {kind!r}")

    def ratio(self, omega):
        """Damping ratio at circular frequency omega (rad/s)."""
        return self.a0 / (2.0 * omega) + self.a1 * omega / 2.0

    def apply(self, model):
        """The model with this damping (no recompile)."""
        return model.with_params(damping=jnp.asarray([self.a0, self.a1], jnp.float64))


def step_solver(state, params, dt, topo, terms, ig: Integrator, start=None, parallel=False):
    """One time step of ``dt`` (s) from ``state`` as the parts of its Newton loop:
    ``(kin, parts)``, ``kin`` as in :meth:`Integrator.equations` and ``parts`` a
    :class:`newton.NewtonParts`. ``start``: the integrator's :meth:`~Integrator.init` of
    ``state`` where known.
    :func:`make_step` runs the parts in a loop of their own, a batch's driver one
    iteration per design at a time. ``parallel``: Newton's line search makes its trials
    at once (:func:`newton.newton_parts`), as a batch off the CPU does."""
    if start is None:
        start = ig.init(state, params, topo, terms)
    kin, residual = ig.equations(state, start, params, dt, topo, terms)
    if ig.predictor == "tangent":
        # Euler (tangent) predictor. From the last q, the prescribed motion of the step
        # distorts the stiffest elements next to a moving support (a bristle root carried
        # by the actuated body: 12 EI / l^3 ~ 1e7 N/mm for 100 elements per bristle).
        # The residual of that distortion is nonlinear at relative order (shift / l), and
        # its second-order part, tens of N, is large for the soft bending modes: the first
        # Newton correction then rotates the whole bristle and Newton diverges at a few
        # um of support motion per step. Linearising the residual in the motion instead,
        # J dq = -(R(q0, t0) + dR/dtc dt), carries the free nodes along (a rigid
        # translation is in the null space of J's elastic part) at the cost of one
        # Newton iteration, which it replaces when nothing is prescribed (dR/dtc = 0).
        # (Extrapolating with v and a was tried earlier and dropped: for steps far above
        # the period, Omega = 1e3 in the HHT check, it lands Newton on another root.)
        # The predictor is Newton's iteration 0 (see newton's ``predict``).
        predict = (state.t, state.t + dt, dt)
    else:
        predict = None
    xscale = jnp.linalg.norm(params.X)
    parts = newton_parts(
        residual, state.q, topo, ig.newton, xscale=xscale, predict=predict, parallel=parallel
    )
    return kin, parts


def step_result(state, params, dt, kin, solved, topo, terms, ig: Integrator):
    """``(state, StepInfo)`` after a time step of ``dt`` from ``state`` whose Newton loop
    ended with ``solved`` = (q, iterations, |R|, F, status): the state at the end of the
    step with the terms' histories committed, or ``state`` itself where the step failed,
    Newton's or one of the checks of a converged state (rotation, penetration, overflow,
    damping)."""
    q1, it, rn, F, status = solved
    t1 = state.t + dt
    u1, v1, a1 = kin(q1)
    h1 = commit_all(terms, u1, v1, t1, state.history, params)
    # The paper crawler's front tip node once turned by 5.33 rad (2 pi - 0.95) in a
    # 27 us step and gained 2.9 mJ of kinetic energy from nothing: a root that exists
    # only because the energy is 2 pi-periodic in the nodal rotations.
    turned = jnp.max(jnp.abs(u1[:, 2] - state.u[:, 2]), initial=0.0) > ig.max_rotation
    status = jnp.where((status == SUCCESS) & turned, ROTATION_LIMIT, status)
    if math.isfinite(ig.penetration_limit):
        # A converged state with a contact point deep in a solid is a wrong root: with
        # penalty contact a rigid corner that reaches the medial axis of a thin beam
        # end is pushed out through the other face (tunnelling); a smaller step keeps
        # Newton's iterates near the contact surface.
        too_deep = max_penetration(terms, h1, params) > ig.penetration_limit
        status = jnp.where((status == SUCCESS) & too_deep, PENETRATION, status)
    status = flag_overflow(terms, u1, params, status)
    if not topo.stiffness_damping:
        # The program has no K v term: parameters that need one are refused, not ignored.
        status = jnp.where(params.damping[1] != 0.0, UNSUPPORTED_DAMPING, status)
    new = DynState(t1, q1, u1, v1, a1, h1)
    good = status == SUCCESS
    out = jax.tree.map(lambda n, o: jnp.where(good, n, o), new, state)
    info = StepInfo(status, it, rn, rn / jnp.maximum(F, 1e-300), t1, dt, 1.0 + 0.0 * dt)
    return out, info


@functools.lru_cache(maxsize=64)
def make_step(topo, terms=(), integrator: Integrator | None = None):
    """Jitted ``step(state, params, dt) -> (state, StepInfo)`` for one topology.

    On failure the returned state is the input state (so a driver can cut dt and retry).
    Works under ``jax.vmap`` over (state, params) batches of the same topology.
    """
    ig = Integrator.hht() if integrator is None else integrator

    @jax.jit
    def step(state, params, dt):
        kin, parts = step_solver(state, params, dt, topo, terms, ig)
        solved = parts.result(jax.lax.while_loop(parts.cond, parts.body, parts.init))
        return step_result(state, params, dt, kin, solved, topo, terms, ig)

    return stored(step, "fe.dynamics.make_step", topo, terms, ig)


@functools.lru_cache(maxsize=64)
def _initial_acceleration_fn(topo, terms):
    """Jitted ``(q, t, history, params) -> (u, a)``: one compiled program, so a run's start
    does not dispatch (and compile) the residual op by op (70 s of the paper crawler's start,
    timed under a profiler)."""
    from bristlecrawler.fe.modal import mass_fn as _mass_fn

    @jax.jit
    def fn(q, t, history, params):
        def expand(q):
            return assembly.expand(q, t, 1.0, params, topo)

        u = expand(q)
        r, _ = force(u, jnp.zeros_like(u), t, history, params, topo, terms)
        if not topo.n_red:
            return u, jnp.zeros_like(u)
        _, pull = jax.vjp(expand, q)
        M = _mass_fn(topo)(q, params, t, jnp.asarray(1.0))
        ar = banded.solve(M, -pull(r)[0], topo)
        return u, jax.jvp(expand, (q,), (ar,))[1]

    return stored(fn, "fe.dynamics.initial_acceleration", topo, terms)


def initial_state(model, u=None, q=None, t: float = 0.0, history=None) -> DynState:
    """Dynamic state at rest at time ``t`` (s), from a static state's ``q`` (or zeros).

    The initial acceleration is the one consistent with the equations of motion, a0 =
    J M_r^-1 J^T (f_ext - f_int - r_k), M_r = J^T M J (rest: no damping, no velocity terms);
    it is zero at a static equilibrium.
    """
    topo, params = model.topology, model.params
    q = jnp.zeros(topo.n_red) if q is None else jnp.asarray(q, jnp.float64)
    hist = init_histories(model) if history is None else history
    tt = jnp.asarray(float(t), jnp.float64)
    u, a = _initial_acceleration_fn(topo, model.terms)(q, tt, hist, params)
    return DynState(tt, q, u, jnp.zeros_like(u), a, hist)


def energy(state: DynState, model) -> dict[str, float]:
    """Kinetic, strain and dead-load potential energy (mJ) of a state."""
    p, topo = model.params, model.topology
    T = float(assembly.kinetic_energy(state.v, p, topo))
    V = float(assembly.internal_energy(state.u, p, topo))
    W = float(jnp.sum(assembly.external_force(state.t, 1.0, p, topo) * state.u))
    return {"kinetic": T, "strain": V, "load_potential": -W, "total": T + V - W}
