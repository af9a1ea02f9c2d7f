"""Static equilibrium: Newton with line search and adaptive load stepping.

Solves J^T [f_int(u) + sum r_k(u, 0, t, h_k) - lam f_ext(t)] = 0 with u = expand(q, t, lam)
for lam from ``lam_start`` to 1 (loads, gravity, prescribed motions and link stretches
ramped together). The increment is halved when Newton fails and grown after an easy
increment (:class:`StepControl`), between ``min_increment`` and ``max_increment``.
"""

from __future__ import annotations

import dataclasses
import functools
from typing import Any

import jax
import jax.numpy as jnp
import numpy as np

from bristlecrawler._pytree import pytree
from bristlecrawler.fe import assembly, banded
from bristlecrawler.fe.control import DEFAULT_CONTROL, StepControl, march
from bristlecrawler.fe.newton import NewtonOptions, newton
from bristlecrawler.fe.options import compose
from bristlecrawler.fe.programs import stored
from bristlecrawler.fe.status import (
    ROTATION_LIMIT,
    STEP_TOO_SMALL,
    SUCCESS,
    StepInfo,
    message,
)
from bristlecrawler.fe.terms import commit_all, flag_overflow, init_histories


@pytree()
class StaticState:
    """Equilibrium state: q reduced unknowns, u full displacements (n_nodes, 3) [mm, rad],
    history of the extra terms, time t (s) and load factor lam."""

    q: Any
    u: Any
    history: tuple
    t: Any
    lam: Any


#: Each load increment's Newton settings by default.
STATIC_NEWTON = NewtonOptions(tolerance=1e-10, max_iterations=30)


@dataclasses.dataclass(frozen=True)
class StaticOptions:
    """Load stepping: ``newton`` (:class:`NewtonOptions`, each increment's solve; default
    tolerance 1e-10, 30 iterations), ``control`` (:class:`StepControl`: an increment is
    halved when it fails and grown after an easy one), ``increments``: initial number of
    load increments; ``min_increment``, ``max_increment``: the increment's bounds;
    ``max_rotation``: largest nodal rotation change (rad) accepted in one increment.
    Rotations enter the energy only modulo 2 pi (local rotations are wrapped), so an
    over-long increment can land on a state whose nodal rotations are off by 2 pi;
    limiting the increment keeps the rotation field continuous along the load path.

    The parts' settings can be given as keywords of their names
    (``StaticOptions(tolerance=1e-12, grow=2.0)``)."""

    newton: NewtonOptions = STATIC_NEWTON
    control: StepControl = DEFAULT_CONTROL
    increments: int = 1
    min_increment: float = 1e-4
    max_increment: float = 1.0
    max_rotation: float = 1.0

    def __init__(
        self,
        newton=None,
        control=None,
        *,
        increments=1,
        min_increment=1e-4,
        max_increment=1.0,
        max_rotation=1.0,
        **settings,
    ):
        parts = {
            "newton": STATIC_NEWTON if newton is None else newton,
            "control": DEFAULT_CONTROL if control is None else control,
        }
        parts = compose("StaticOptions", parts, settings)
        values = parts | {
            "increments": increments,
            "min_increment": min_increment,
            "max_increment": max_increment,
            "max_rotation": max_rotation,
        }
        for name, value in values.items():
            object.__setattr__(self, name, value)


@dataclasses.dataclass(frozen=True)
class StaticResult:
    """Final state, per-increment infos, success flag and message."""

    state: StaticState
    infos: list
    ok: bool
    message: str


def static_residual(q, t, lam, history, params, topo, terms):
    """Reduced static residual and force scale F (N)."""
    u, pull = jax.vjp(lambda q: assembly.expand(q, t, lam, params, topo), q)
    f_int = assembly.internal_force(u, params, topo)
    f_ext = assembly.external_force(t, lam, params, topo)
    f_t = assembly.terms_residual(u, jnp.zeros_like(u), t, history, params, terms)
    (R,) = pull(f_int + f_t - f_ext)
    F = jnp.linalg.norm(f_int) + jnp.linalg.norm(f_ext) + jnp.linalg.norm(f_t)
    return R, F


@functools.lru_cache(maxsize=64)
def make_static_solver(topo, terms, newton_options):
    """Jitted ``solve(q0, params, t, lam, history) -> (q, u, StepInfo)`` for one topology."""

    @jax.jit
    def solve(q0, params, t, lam, history):
        def res(q):
            return static_residual(q, t, lam, history, params, topo, terms)

        q, it, rn, F, status = newton(
            res, q0, topo, newton_options, xscale=jnp.linalg.norm(params.X)
        )
        u = assembly.expand(q, t, lam, params, topo)
        status = flag_overflow(terms, u, params, status)
        info = StepInfo(status, it, rn, rn / jnp.maximum(F, 1e-300), t, 0.0 * t, lam)
        return q, u, info

    return stored(solve, "fe.static.solver", topo, terms, newton_options)


def initial_static_state(model, t: float = 0.0) -> StaticState:
    """Undeformed state (q = 0, lam = 0) at time t."""
    topo = model.topology
    q = jnp.zeros(topo.n_red)
    u = assembly.expand(q, t, 0.0, model.params, topo)
    return StaticState(q, u, init_histories(model), jnp.asarray(float(t)), jnp.asarray(0.0))


def solve_static(
    model,
    t: float = 0.0,
    state: StaticState | None = None,
    options: StaticOptions | None = None,
    check_support: bool | None = None,
    throw: bool = True,
) -> StaticResult:
    """Equilibrium at time ``t`` (s) and load factor 1, by load stepping from ``state``.

    ``check_support`` (default: when the model has no extra terms) first refuses a
    structure whose stiffness is singular (under-constrained) with InputError.
    """
    options = StaticOptions() if options is None else options
    topo, params = model.topology, model.params
    if check_support is None:
        check_support = not model.terms
    if check_support:
        check_supported(model, t)
    solver = make_static_solver(topo, model.terms, options.newton)
    state = initial_static_state(model, t) if state is None else state
    lam = float(state.lam) if float(state.t) == float(t) else 0.0
    dlam = min(options.max_increment, 1.0 / max(options.increments, 1))
    infos: list = []
    tt = jnp.asarray(float(t))

    def attempt(at, h):
        # at: the load factor, unknowns and committed histories of the last increment
        lam0, q0, h0 = at
        target = 1.0 if h >= 1.0 - lam0 else lam0 + h
        q1, u1, info = solver(q0, params, tt, jnp.asarray(target), h0)
        u_prev = assembly.expand(q0, t, lam0, params, topo)
        too_far = float(jnp.max(jnp.abs(u1[:, 2] - u_prev[:, 2]))) > options.max_rotation
        status = int(info.status)
        if too_far and status == SUCCESS:
            status = ROTATION_LIMIT
        if status != SUCCESS:  # refused: nothing to commit
            return at, info, status, None
        h1 = commit_all(model.terms, u1, jnp.zeros_like(u1), t, h0, params)
        return (target, q1, h1), info, status, None

    at = (lam, state.q, state.history)
    lo, hi = options.min_increment, options.max_increment
    for a in march(attempt, at, lam, 1.0, dlam, lo, hi, options.control, time_of=lambda n: n[0]):
        out, info = a.outcome, a.info
        if out.status != int(info.status):
            info = dataclasses.replace(info, status=jnp.asarray(out.status))
        infos.append(info)
        if out.good:
            at = a.new
        elif out.failed:
            lam, q, hist = at
            where = f"static solve, increment {len(infos)}"
            msg = message(info, where)
            if out.status == STEP_TOO_SMALL:
                msg += f"; increment cut below {options.min_increment:g}"
            if throw:
                from bristlecrawler.errors import SolverError

                raise SolverError(msg)
            u = assembly.expand(q, t, lam, params, topo)
            return StaticResult(
                StaticState(q, u, hist, jnp.asarray(float(t)), jnp.asarray(lam)), infos, False, msg
            )
    _, q, hist = at
    u = assembly.expand(q, t, 1.0, params, topo)
    final = StaticState(q, u, hist, jnp.asarray(float(t)), jnp.asarray(1.0))
    return StaticResult(final, infos, True, "converged")


@functools.lru_cache(maxsize=64)
def _tangent_fn(topo, terms):
    @jax.jit
    def fn(q, params, t, lam, history):
        def res(q):
            return static_residual(q, t, lam, history, params, topo, terms)[0]

        return banded.extract(res, q, topo)[1]

    return stored(fn, "fe.static.tangent", topo, terms)


def tangent(model, q, t: float = 0.0, lam: float = 1.0, history=None):
    """Reduced tangent stiffness at ``q`` as a :class:`banded.BlockSystem` (compiled)."""
    history = init_histories(model) if history is None else history
    fn = _tangent_fn(model.topology, model.terms)
    return fn(jnp.asarray(q), model.params, jnp.asarray(float(t)), jnp.asarray(float(lam)), history)


def linear_solve(model, load, t: float = 0.0):
    """Small-displacement response K u = f about the reference state (full u, mm / rad).

    ``load``: full nodal force vector (n_nodes, 3) [N, N, N mm]; prescribed DOFs stay 0.
    """
    topo = model.topology
    q0 = jnp.zeros(topo.n_red)
    K = tangent(model, q0, t, 0.0)

    def expand(q):
        return assembly.expand(q, t, 0.0, model.params, topo)

    _, pull = jax.vjp(expand, q0)
    q = banded.solve(K, pull(jnp.asarray(load))[0], topo)
    return jax.jvp(expand, (q0,), (q,))[1]


def check_supported(model, t: float = 0.0) -> None:
    """InputError naming a DOF if the stiffness at the reference state is singular.

    The tangent is scaled to unit diagonal and factorised (SuperLU); a pivot below 1e-10
    of the largest flags a mechanism (a free rigid motion or an unrestrained rotation).
    """
    import scipy.sparse as sp
    import scipy.sparse.linalg as spla

    from bristlecrawler.errors import InputError

    topo = model.topology
    if topo.n_red == 0:
        return
    K = banded.to_scipy(tangent(model, jnp.zeros(topo.n_red), t, 0.0), topo)
    K = 0.5 * (K + K.T)
    d = np.abs(K.diagonal())
    zero = np.flatnonzero(d <= 1e-14 * max(d.max(), 1e-300))
    if zero.size:
        raise InputError(
            f"under-constrained structure: no stiffness on {topo.dof_label(int(zero[0]))} "
            "(add a support, spring or contact)"
        )
    s = sp.diags(1.0 / np.sqrt(d))
    lu = spla.splu((s @ K @ s).tocsc(), permc_spec="NATURAL", diag_pivot_thresh=1.0)
    piv = np.abs(lu.U.diagonal())
    k = int(np.argmin(piv))
    if piv[k] < 1e-10 * piv.max():
        raise InputError(
            f"under-constrained structure: stiffness singular (mechanism) at "
            f"{topo.dof_label(int(lu.perm_c[k]))} (add a support, spring or contact)"
        )
