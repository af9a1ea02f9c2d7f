"""Implicit dynamics: Newmark and HHT-alpha, Rayleigh damping, adaptive time steps.

HHT-alpha (Hilber, Hughes & Taylor 1977; Hughes, *The Finite Element Method*, 2000,
Sec. 9.3.3), Abaqus sign convention alpha in [-1/3, 0] (default -0.05),
beta = (1 - alpha)^2 / 4, gamma = 1/2 - alpha:

    M a1 + (1 + alpha) r(u1, v1, t1) - alpha r(u0, v0, t0) = 0,
    r = C v + f_int(u) + sum_k r_k(u, v, t, h_k) - f_ext(t),
    u1 = u0 + dt v0 + dt^2 ((1/2 - beta) a0 + beta a1),  v1 = v0 + dt ((1 - gamma) a0 + gamma a1).

alpha = 0 is Newmark (beta, gamma free; 1/4, 1/2 = trapezoidal rule, energy conserving for
linear systems). Kinematics are integrated for the *full* nodal vectors and the constraints
(supports, rigid links, the actuated body) are imposed at t1 through u1 = expand(q1, t1);
the residual is projected by J^T = (d expand / dq)^T. This is the index-3 Lagrange-multiplier
HHT with the multipliers eliminated by the null-space (Jacobian) basis.

Rayleigh damping C v = a0 M v + a1 K_T(u) v, with K_T v a JVP of the internal force
(left out of the programs of a topology built without stiffness damping,
:func:`assembly.internal_and_damping_force`).
"""

from __future__ import annotations

import dataclasses
import functools
import math
from typing import Any

import jax
import jax.numpy as jnp
import numpy as np

from bristlecrawler._pytree import pytree
from bristlecrawler.errors import InputError, SolverError
from bristlecrawler.fe import assembly, banded
from bristlecrawler.fe.control import DEFAULT_CONTROL, StepControl, march
from bristlecrawler.fe.newton import DEFAULT_NEWTON, NewtonOptions, newton_parts
from bristlecrawler.fe.options import compose, renamed
from bristlecrawler.fe.programs import stored
from bristlecrawler.fe.status import (
    PENETRATION,
    ROTATION_LIMIT,
    STEP_TOO_SMALL,
    SUCCESS,
    UNSUPPORTED_DAMPING,
    StepInfo,
    message,
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


@renamed(max_penetration="penetration_limit")
@dataclasses.dataclass(frozen=True)
class Integrator:
    """Time integration scheme and the Newton settings of its steps (static: part of the
    compiled step).

    Use :meth:`hht` (default alpha = -0.05) or :meth:`newmark`; either takes the Newton
    settings as ``newton=NewtonOptions(...)`` or as keywords of the same names
    (``Integrator.hht(tolerance=1e-12, max_iterations=8)``). Their meanings are
    :class:`NewtonOptions`'s; in a step, the convergence test's force scale F is the sum
    of the inertial, internal, damping and external force norms (N), ``stall_iterations``
    and a failed line search cut the step, and ``freeze_iterations`` counts the
    predictor. ``max_correction`` does not cap the predictor; with
    ``predictor="constant"`` it caps the first correction.

    penetration_limit: a converged step whose committed contact state has a penetration
    deeper than this (mm; terms that report one, see :mod:`terms`) is rejected with status
    PENETRATION, so an adaptive driver cuts it (default: no limit).
    max_rotation: largest nodal rotation change (rad) accepted in one step, as in statics:
    rotations enter the energy only modulo 2 pi, so Newton can converge to a state with a
    node turned by about 2 pi (a kick of spurious kinetic energy); such a step is rejected
    with status ROTATION_LIMIT and cut.
    predictor: "tangent" (default) starts Newton from q0 + dq with J dq = -(R + dR/dt dt),
    the residual *linearised* in the step's change of the prescribed motions (supports,
    link stretches); "constant" starts from the last converged q. See :func:`make_step`.
    """

    alpha: float = -0.05
    beta: float = 0.25 * 1.05**2
    gamma: float = 0.55
    newton: NewtonOptions = DEFAULT_NEWTON
    predictor: str = "tangent"
    penetration_limit: float = math.inf
    max_rotation: float = 1.0

    def __init__(
        self,
        alpha=-0.05,
        beta=0.25 * 1.05**2,
        gamma=0.55,
        newton=None,
        *,
        predictor="tangent",
        penetration_limit=math.inf,
        max_rotation=1.0,
        **settings,
    ):
        newton = DEFAULT_NEWTON if newton is None else newton
        newton = compose("Integrator", {"newton": newton}, settings)["newton"]
        for name, value in (
            ("alpha", alpha),
            ("beta", beta),
            ("gamma", gamma),
            ("newton", newton),
            ("predictor", predictor),
            ("penetration_limit", penetration_limit),
            ("max_rotation", max_rotation),
        ):
            object.__setattr__(self, name, value)
        self.__post_init__()

    def __post_init__(self) -> None:
        if not isinstance(self.newton, NewtonOptions):
            raise InputError(f"newton must be a NewtonOptions, got {self.newton!r}")
        if not self.max_rotation > 0.0:
            raise InputError(f"max_rotation must be > 0 rad, got {self.max_rotation}")
        if not self.penetration_limit > 0.0:
            raise InputError(f"penetration_limit must be > 0 mm, got {self.penetration_limit}")
        if self.predictor not in ("tangent", "constant"):
            raise InputError(f"predictor must be 'tangent' or 'constant', got {self.predictor!r}")

    @classmethod
    def hht(cls, alpha: float = -0.05, **kw) -> Integrator:
        """HHT-alpha, alpha in [-1/3, 0]."""
        if not (-1.0 / 3.0 <= alpha <= 0.0):
            raise InputError(f"HHT alpha must be in [-1/3, 0], got {alpha}")
        return cls(alpha, (1.0 - alpha) ** 2 / 4.0, 0.5 - alpha, **kw)

    @classmethod
    def newmark(cls, beta: float = 0.25, gamma: float = 0.5, **kw) -> Integrator:
        """Newmark; the default (1/4, 1/2) is the trapezoidal rule."""
        if not (beta > 0.0 and gamma >= 0.5):
            raise InputError(f"Newmark needs beta > 0 and gamma >= 1/2, got {beta}, {gamma}")
        return cls(0.0, beta, gamma, **kw)


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


def _force(u, v, t, history, params, topo, terms, freeze=False, masses=None):
    """r = C v + f_int + terms - f_ext (full) and its force scale (``freeze``: see
    :func:`assembly.terms_residual`; ``masses``: :func:`assembly.element_masses`)."""
    f_int, damp = assembly.internal_and_damping_force(u, v, params, topo, masses)
    f_t = assembly.terms_residual(u, v, t, history, params, terms, freeze)
    f_ext = assembly.external_force(t, 1.0, params, topo, masses)
    scale = sum(jnp.linalg.norm(x) for x in (f_int, damp, f_t, f_ext))
    return damp + f_int + f_t - f_ext, scale


def _masses(params, topo):
    return assembly.element_masses(params, topo) if topo.elems else None


def start_force(state, params, topo, terms, masses=None):
    """The force at ``state`` (the r of :func:`_force`) and its scale: the start of a time
    step's HHT residual, the same for every iterate and every step size from it."""
    if masses is None:
        masses = _masses(params, topo)
    return _force(state.u, state.v, state.t, state.history, params, topo, terms, masses=masses)


def step_equations(state, params, dt, topo, terms, ig: Integrator, start=None):
    """The equations of one time step of ``dt`` (s) from ``state``: ``kin(q, tc)``, the
    full (u, v, a) at the end of the step for reduced unknowns ``q`` (prescribed motions
    at time ``tc``, default the step's end), and ``residual(q, tc, freeze)``, the HHT
    residual in the reduced unknowns and its force scale (see the module; ``freeze``:
    :func:`assembly.terms_residual`). ``start``: :func:`start_force` of ``state`` where
    known."""
    al, be, ga = ig.alpha, ig.beta, ig.gamma
    t1 = state.t + dt
    u0, v0, a0 = state.u, state.v, state.a
    # Element masses once per step, not once per residual (three products M x each).
    Me = _masses(params, topo)
    r0, s0 = start_force(state, params, topo, terms, Me) if start is None else start

    def newmark(u):
        a = (u - u0 - dt * v0) / (be * dt**2) - (0.5 / be - 1.0) * a0
        v = v0 + dt * ((1.0 - ga) * a0 + ga * a)
        return u, v, a

    def kin(q, tc=t1):
        # tc: time of the prescribed motions (supports, link stretches) in expand
        return newmark(assembly.expand(q, tc, 1.0, params, topo))

    def residual(q, tc=t1, freeze=False):
        # One expansion gives u and, transposed, the projection of the full residual.
        u, pull = jax.vjp(lambda q: assembly.expand(q, tc, 1.0, params, topo), q)
        u, v, a = newmark(u)
        r1, s1 = _force(u, v, t1, state.history, params, topo, terms, freeze, Me)
        Ma = assembly.mass_times(a, params, topo, Me)
        full = Ma + (1.0 + al) * r1 - al * r0
        (R,) = pull(full)
        return R, jnp.linalg.norm(Ma) + s1 + jnp.abs(al) * s0

    return kin, residual


def step_solver(state, params, dt, topo, terms, ig: Integrator, start=None, parallel=False):
    """One time step of ``dt`` (s) from ``state`` as the parts of its Newton loop:
    ``(kin, parts)``, ``kin`` as in :func:`step_equations` and ``parts`` a
    :class:`newton.NewtonParts`. ``start``: :func:`start_force` of ``state`` where known.
    :func:`make_step` runs the parts in a loop of their own, a batch's driver one
    iteration per design at a time. ``parallel``: Newton's line search makes its trials
    at once (:func:`newton.newton_parts`), as a batch off the CPU does."""
    kin, residual = step_equations(state, params, dt, topo, terms, ig, start)
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
        r, _ = _force(u, jnp.zeros_like(u), t, history, params, topo, terms)
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


@dataclasses.dataclass(frozen=True)
class DynResult:
    """Adaptive run: final state, accepted times (s), observed values, infos, ok, message."""

    state: DynState
    times: np.ndarray
    observed: list
    infos: list
    ok: bool
    message: str
    rejected: int


def integrate(
    model,
    state: DynState,
    t_end: float,
    dt: float,
    *,
    integrator: Integrator | None = None,
    dt_min: float | None = None,
    dt_max: float | None = None,
    control: StepControl = DEFAULT_CONTROL,
    observe=None,
    throw: bool = True,
) -> DynResult:
    """Adaptive time stepping from ``state`` to ``t_end`` (s), starting with step ``dt`` (s).

    A step that fails (Newton limit, NaN) is retried with dt/2 (but a fatal status,
    :data:`status.FATAL`, which a smaller step cannot cure, ends the run); after an easy
    step it grows (``control``, :class:`StepControl`); dt stays in
    [dt_min, dt_max] (defaults dt/1e4 and dt). ``observe(state) -> anything`` is recorded
    after every accepted step. Returns :class:`DynResult`; raises SolverError if ``throw``
    and dt falls below dt_min.
    """
    if not (dt > 0.0 and math.isfinite(dt)):
        raise InputError(f"dt must be positive, got {dt}")
    dt_min = dt * 1e-4 if dt_min is None else dt_min
    dt_max = dt if dt_max is None else dt_max
    step = make_step(model.topology, model.terms, integrator)
    params = model.params
    times, observed, infos = [], [], []
    rejected = 0

    def attempt(state, h):
        new, info = step(state, params, jnp.asarray(h))
        infos.append(info)
        return new, info, int(info.status), None

    tries = march(
        attempt,
        state,
        float(state.t),
        t_end,
        dt,
        dt_min,
        dt_max,
        control,
        time_of=lambda s: float(s.t),
    )
    for a in tries:
        out = a.outcome
        if out.good:
            state = a.new
            times.append(float(state.t))
            if observe is not None:
                observed.append(observe(state))
            continue
        rejected += 1
        if out.failed:
            where = f"dynamics, step {len(times) + 1}"
            msg = message(a.info, where)
            if out.status == STEP_TOO_SMALL:
                msg += f"; dt cut below dt_min = {dt_min:g} s"
                infos[-1] = dataclasses.replace(a.info, status=jnp.asarray(STEP_TOO_SMALL))
            if throw:
                raise SolverError(msg)
            return DynResult(state, np.asarray(times), observed, infos, False, msg, rejected)
    return DynResult(state, np.asarray(times), observed, infos, True, "converged", rejected)


def run_fixed(
    model_or_topology,
    state: DynState,
    params,
    dt: float,
    n_steps: int,
    integrator: Integrator | None = None,
    terms=(),
):
    """``n_steps`` steps of fixed ``dt`` in one compiled ``lax.scan`` (batched runs, bench).

    Returns (final state, StepInfo stacked over steps). A failed step leaves the state
    unchanged, so check the infos (:func:`status.check`).
    """
    topo = getattr(model_or_topology, "topology", model_or_topology)
    terms = getattr(model_or_topology, "terms", terms)
    step = make_step(topo, terms, integrator)
    return _scan(step, state, params, jnp.asarray(dt), n_steps)


@functools.partial(jax.jit, static_argnums=(0, 4))
def _scan(step, state, params, dt, n_steps):
    def body(s, _):
        s, info = step(s, params, dt)
        return s, info

    return jax.lax.scan(body, state, None, length=n_steps)
