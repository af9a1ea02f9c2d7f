"""Contact verification cases run through the FE solvers (frictional contact).

Each case builds a small structure with the :class:`~bristlecrawler.contact.term.
SubstrateContact` term, runs the FE dynamic solver (HHT-alpha, alpha = -0.05), and is
compared with the analytic references of :mod:`bristlecrawler.verification.contact_refs`,
which are computed independently of the FE code.

This module: the block cases, on :func:`block_on_plane` (a point mass pulled by a long
spring whose far end follows a ramp, on a flat Coulomb plane): the Coulomb oscillator
(ramp 0) and the block on an incline pushed horizontally (gravity turned into the plane's
frame). Both have one topology, so they share one compiled time step. The beam cases are
in :mod:`bristlecrawler.verification.contact_beam_cases`.
"""

from __future__ import annotations

import functools
import itertools
import math
from typing import NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from bristlecrawler import fe
from bristlecrawler.contact import SLIP, STICK, CoulombLaw, Flat
from bristlecrawler.contact.term import SubstrateContact
from bristlecrawler.fe.control import march
from bristlecrawler.fe.motion import Ramp
from bristlecrawler.verification.contact_refs import (
    DEFAULT_OSCILLATOR,
    G_MM_S2,
    OscillatorHistory,
    OscillatorParams,
    coulomb_oscillator,
    incline_push_ratio,
)

#: Length of the driving spring of the block cases, mm: it stays parallel to its drive
#: direction to O(displacement / length) = 1e-5 rad.
SPRING_LENGTH = 1e4
HHT = fe.Integrator.hht()


# --------------------------------------------------------------------------------------------
# shared drivers
# --------------------------------------------------------------------------------------------


@functools.lru_cache(maxsize=8)
def _initial_state_fn(topo, terms):
    """Compiled :func:`fe.initial_state` (consistent initial acceleration) for a topology;
    op-by-op it would compile dozens of small kernels."""

    @jax.jit
    def fn(params, q, history):
        return fe.initial_state(fe.Model(topo, params, terms), q=q, history=history)

    return fn


@functools.partial(jax.jit, static_argnums=0)
def history_at(term, u, params):
    """Compiled ``term.history_at``: every contact point stuck where it is at ``u``."""
    return term.history_at(u, params)


def start_at(model, q, history):
    """Dynamic state at rest at ``q`` with the contact ``history``, with the consistent
    initial acceleration."""
    return _initial_state_fn(model.topology, model.terms)(model.params, q, (history,))


def run(model, state, t_end, dt, observe, integrator=HHT):
    """Adaptive HHT run (:func:`fe.solve`: steps of ``dt`` s, halved when Newton fails);
    returns the :class:`fe.Solution` and host copies of ``observe(state)`` (jittable),
    one per accepted step."""

    def save(st, params):
        return {"t": st.t, "observed": observe(st)}

    res = fe.solve(model, state, t_end, dt, integrator=integrator, save=fe.SaveAt(save))
    rows = jax.device_get(res.records["observed"]) if res.steps else None
    return res, [jax.tree.map(lambda x, i=i: x[i], rows) for i in range(res.steps)]


class ResolvedRun(NamedTuple):
    """Result of :func:`run_resolving`: accepted times (s), observations, steps cut."""

    times: np.ndarray
    observed: list
    rejected: int


@jax.jit
def _slip_dp(old, new):
    """Largest change of the normal force (N) over the contact points slipping in a step."""
    slipping = (old.state == SLIP) | (new.state == SLIP)
    return jnp.max(jnp.where(slipping, jnp.abs(new.p_n - old.p_n), 0.0))


def run_resolving(
    model,
    state,
    t_end,
    dt,
    observe,
    max_dp,
    integrator=HHT,
    dt_min=None,
    dt_floor=None,
    control=None,
):
    """Time stepping as :func:`fe.solve` (the rules of ``control``, a
    :class:`fe.StepControl`, default its defaults; steps <= ``dt`` s), and a converged step
    is also cut when the normal force of a slipping contact point changes by more than
    ``max_dp`` N in it.

    Why: the return mapping dissipates ``mu p_N |Delta anchor|`` with the normal force of
    the step's end (backward Euler), while the work done on the beam follows the forces
    through the step; when p_N changes during slip the two differ by about
    ``1/2 mu |Delta p_N| |Delta anchor|`` per step. Where a tip slides off a corner, p_N
    falls to zero within a few steps of fast slip and this first-order error, of one sign,
    adds up to 1e-3 of the work in; bounding Delta p_N makes it ``1/2 mu max_dp`` times
    the slip of the event. Steps are not cut for accuracy below ``dt_floor`` (default
    dt / 16): far below it the penalty modes of the contact (omega ~ 1e6 rad/s) would be
    resolved, and they ring instead of being damped by the scheme.
    ``observe(state)`` is recorded after every accepted step.
    Raises SolverError if a step must be cut below ``dt_min`` (default dt / 1e4).
    """
    from bristlecrawler.errors import SolverError
    from bristlecrawler.fe.status import STEP_ERROR, STEP_TOO_SMALL, SUCCESS, message

    control = control or fe.StepControl()
    dt_min = dt * 1e-4 if dt_min is None else dt_min
    dt_floor = dt / 16.0 if dt_floor is None else dt_floor
    step = fe.make_step(model.topology, model.terms, integrator)
    params = model.params
    times, observed, rejected = [], [], 0

    def attempt(state, h):
        new, info = step(state, params, jnp.asarray(h))
        status = int(info.status)
        if status == SUCCESS and h > dt_floor:
            if float(_slip_dp(state.history[0], new.history[0])) > max_dp:
                status = STEP_ERROR  # converged, but too long for the slip's accuracy
        return new, info, status, None

    t0 = float(state.t)
    for a in march(attempt, state, t0, t_end, dt, dt_min, dt, control, time_of=_time):
        out = a.outcome
        if out.good:
            times.append(float(a.new.t))
            observed.append(observe(a.new))
            continue
        rejected += 1
        if out.failed:
            msg = message(a.info, f"dynamics, step {len(times) + 1}")
            cut = out.status == STEP_TOO_SMALL
            raise SolverError(msg + (f"; dt cut below dt_min = {dt_min:g} s" if cut else ""))
    return ResolvedRun(np.asarray(times), jax.device_get(observed), rejected)


def _time(state) -> float:
    return float(state.t)


def slip_onset(load, f_t, p_n, states, mu):
    """Load at which a stuck contact reaches the friction limit ``|f_t| = mu p_N``.

    The onset is the first slip step that follows two stick steps (a touchdown may slip
    for a step before it sticks: with a normal force near zero any tangential motion
    exceeds the limit). In stick the point is held, so (linear elasticity, slow loading)
    both contact forces are affine in the load: they are extended from the last two stick
    steps and the crossing is solved exactly, which leaves only the nonlinearity within one
    load step as error.
    Returns (load at onset, index of the first slip step); (NaN, -1) if there is none.
    """
    k_all = np.flatnonzero(states == SLIP)
    onsets = [k for k in k_all if k >= 2 and np.all(states[k - 2 : k] == STICK)]
    if not onsets:
        return math.nan, -1
    k = int(onsets[0])
    i, j = k - 2, k - 1
    dl = load[j] - load[i]
    df, dp = (f_t[j] - f_t[i]) / dl, (p_n[j] - p_n[i]) / dl
    s = math.copysign(1.0, f_t[j])
    extra = (mu * p_n[j] - s * f_t[j]) / (s * df - mu * dp)
    return float(load[j] + extra), k


def block_on_plane(mass, stiffness, gravity, pull_dir, drive, duration, law):
    """Point mass at the origin on the plane y = 0, pulled by a spring of length
    :data:`SPRING_LENGTH` along ``pull_dir`` whose far end moves ``drive`` mm along
    ``pull_dir`` in ``duration`` s (a ramp). ``mass`` t, ``stiffness`` N/mm, ``gravity``
    (2,) mm/s^2 in the plane's frame.

    Returns (model, term, mass node). Every call has the same topology and parameter
    structure, so the time-step program compiles once.
    """
    e = np.asarray(pull_dir, float) / np.linalg.norm(pull_dir)
    s = fe.Structure()
    far = s.node(*(SPRING_LENGTH * e))
    s.prescribe(far, "x", Ramp(drive * e[0], duration))
    s.prescribe(far, "y", Ramp(drive * e[1], duration))
    s.fix(far, "theta")
    m = s.node(0.0, 0.0)
    s.fix(m, "theta")
    s.spring(far, m, stiffness)
    s.point_mass(m, mass)
    s.gravity(*gravity)
    term = SubstrateContact((m,))
    X = np.array([SPRING_LENGTH * e, [0.0, 0.0]])
    s.add_term(term, SubstrateContact.params(X, (m,), Flat(), law))
    return s.build(), term, m


def _block_at_rest(model, term, m, x, sink, anchor_shift=0.0):
    """The block at rest at ``x`` mm, sunk ``sink`` mm into the plane (vertical
    equilibrium of the penalty), stuck ``anchor_shift`` mm behind its anchor (a stick force
    ``k_t anchor_shift``)."""
    u = jnp.zeros((2, 3)).at[m, 0].set(x).at[m, 1].set(sink)
    h = history_at(term, u, model.params.extra[0])
    h = type(h)(h.anchor + anchor_shift, h.dissipation, h.state, h.p_n, h.f_t)
    return start_at(model, jnp.array([x, sink]), h)


# --------------------------------------------------------------------------------------------
# 1. Coulomb oscillator
# --------------------------------------------------------------------------------------------


class OscillatorRun(NamedTuple):
    """FE Coulomb oscillator.

    turning_points: the release point (the initial condition, at rest) and the positions
    of the following velocity reversals computed by the solver, the last one where the
    mass sticks for good, mm; turning_times: their times, s; stop_time: time of the final
    stop, s; dissipation: frictional dissipation of the return mapping, mJ;
    energy_loss: spring energy lost between release and rest, mJ; reference: the closed
    form (:class:`~bristlecrawler.verification.contact_refs.OscillatorHistory`).
    """

    turning_points: np.ndarray
    turning_times: np.ndarray
    stop_time: float
    dissipation: float
    energy_loss: float
    reference: OscillatorHistory

    @property
    def energy_balance_rel_error(self) -> float:
        return abs(self.dissipation - self.energy_loss) / self.energy_loss


def _reversals(t, x, v, a, vtol):
    """Times and positions where the velocity changes sign between samples faster than
    ``vtol``, and where it last falls below it (the final stop). Each is extrapolated
    from the slowest sample before it with its acceleration (v = 0 at t_m - v_m / a_m,
    x_m - v_m^2 / (2 a_m)); the error is of the order of the jerk times dt^3."""
    fast = np.flatnonzero(np.abs(v) > vtol)
    idx = []
    for i, j in itertools.pairwise(fast):
        if np.sign(v[i]) != np.sign(v[j]):
            seg = np.arange(i, j + 1)
            before = seg[np.sign(v[seg]) == np.sign(v[i])]
            idx.append(int(before[np.argmin(np.abs(v[before]))]))
    if fast.size:
        idx.append(int(fast[-1]))
    idx = np.asarray(idx, int)
    return t[idx] - v[idx] / a[idx], x[idx] - v[idx] ** 2 / (2.0 * a[idx])


def coulomb_oscillator_fe(
    params: OscillatorParams = DEFAULT_OSCILLATOR, dt: float = 1e-3, t_end: float | None = None
) -> OscillatorRun:
    """Mass on a spring sliding on a flat Coulomb plane, HHT-alpha, steps of ``dt`` s.

    The normal penalty is sized for the weight (penetration 1 micrometre); the mass starts
    at rest at ``x0`` in vertical equilibrium, with its friction force at the slip limit
    mu m g against the spring (the state of the closed form at t = 0+; a block stuck with
    no friction force would start with an acceleration wrong by mu g, an O(dt) phase
    error of the whole run). The spring's far end does not move (ramp of 0 mm).
    """
    ref = coulomb_oscillator(params)
    weight = params.mass * params.gravity
    law = CoulombLaw.for_reference_load(params.mu, load=weight)
    model, term, m = block_on_plane(
        params.mass, params.stiffness, (0.0, -params.gravity), (-1.0, 0.0), 0.0, 1.0, law
    )
    limit = params.mu * weight / float(law.k_t)  # stick drift at the friction limit, mm
    state = _block_at_rest(
        model,
        term,
        m,
        params.x0,
        -weight / float(law.k_n),
        anchor_shift=math.copysign(limit, params.x0),
    )
    t_end = t_end if t_end is not None else ref.stop_time + 0.5
    # HHT (alpha = -0.05) damps the stiff stick-penalty mode (omega dt ~ 3) that the
    # trapezoidal rule would keep ringing; at the oscillator's own frequency
    # (omega dt = 0.01) its algorithmic damping ratio is 6e-9.
    res, obs = run(
        model,
        state,
        t_end,
        dt,
        lambda st: (st.u[m, 0], st.v[m, 0], st.a[m, 0], st.history[0].dissipation[0]),
    )
    x, v, a, diss = (np.array(c) for c in zip(*obs, strict=True))
    t = np.asarray(res.times)
    times, turns = _reversals(t, x, v, a, vtol=1e-3 * params.omega * abs(params.x0))
    tp = np.concatenate([[params.x0], turns])
    tt = np.concatenate([[0.0], times])
    loss = 0.5 * params.stiffness * (params.x0**2 - x[-1] ** 2)
    stop = float(tt[-1]) if tt.size > 1 else 0.0
    return OscillatorRun(tp, tt, stop, float(diss[-1]), float(loss), ref)


# --------------------------------------------------------------------------------------------
# 2. Block on an incline pushed horizontally
# --------------------------------------------------------------------------------------------


class InclineRun(NamedTuple):
    """Block on an incline: push/weight at the onset of sliding (FE), the reference, the
    index of the first slip step, and the block's travel up the slope after it (mm)."""

    ratio: float
    reference: float
    first_slip_step: int
    travel_after_onset: float


def incline_push_fe(
    tan_angle: float = 0.1, mu: float = 0.3, dt: float = 1e-3, steps_to_onset: int = 200
) -> InclineRun:
    """A 1 kg block on an incline, pushed by a horizontal force that grows slowly.

    Computed in the incline's frame: the plane is y = 0 and gravity has components
    g (-sin a, -cos a) (a = atan(tan_angle)); the horizontal of the world is
    (cos a, -sin a) there. The block starts stuck at rest, its stick force holding the
    down-slope weight; a horizontal spring (1 N/mm) pulls it with a force that grows by
    about 1 / ``steps_to_onset`` of the expected onset load per step, so the onset is
    found for a ratio up to 2.5 times the reference, and the run goes on 25% past it.
    The push is the spring force (N) from the FE displacements; its value when the FE
    contact forces reach the friction limit is found with :func:`slip_onset`.
    """
    a = math.atan(tan_angle)
    mass, stiffness = 1e-3, 1.0
    weight = mass * G_MM_S2
    law = CoulombLaw.for_reference_load(mu, load=weight)
    e = np.array([math.cos(a), -math.sin(a)])
    guess = incline_push_ratio(tan_angle, mu)  # only sizes the drive
    t_onset = steps_to_onset * dt
    drive_time = 2.5 * t_onset
    model, term, m = block_on_plane(
        mass,
        stiffness,
        G_MM_S2 * np.array([-math.sin(a), -math.cos(a)]),
        e,
        2.5 * guess * weight / stiffness,
        drive_time,
        law,
    )
    state = _block_at_rest(
        model,
        term,
        m,
        0.0,
        -weight * math.cos(a) / float(law.k_n),
        anchor_shift=weight * math.sin(a) / float(law.k_t),
    )
    X = np.asarray(model.params.X)

    def observe(st):
        h = st.history[0]
        return st.u[:, :2], h.state[0], h.f_t[0], h.p_n[0]

    _, obs = run(model, state, 1.25 * t_onset, dt, observe)
    u, states, f_t, p_n = (np.array(c) for c in zip(*obs, strict=True))
    x = X[None] + u
    push = stiffness * (np.linalg.norm(x[:, 0] - x[:, 1], axis=1) - SPRING_LENGTH)
    onset, k = slip_onset(push, f_t, p_n, states, mu)
    travel = float(x[-1, 1, 0] - x[k, 1, 0]) if k >= 0 else math.nan
    return InclineRun(onset / weight, incline_push_ratio(tan_angle, mu), k, travel)


__all__ = [
    "HHT",
    "SPRING_LENGTH",
    "InclineRun",
    "OscillatorRun",
    "ResolvedRun",
    "block_on_plane",
    "coulomb_oscillator_fe",
    "history_at",
    "incline_push_fe",
    "run",
    "run_resolving",
    "slip_onset",
    "start_at",
]
