"""Contact verification cases of a beam (the paper's bristle) on a substrate.

:func:`beam_on_substrate` (a cantilever whose clamp is lowered and dragged, one contact
point at the tip) serves both cases with one topology and one substrate type, so they
share one compiled time step:

* the pressed-and-dragged bristle on a flat plane (stick, then slip) against the
  linearised reference :func:`~bristlecrawler.verification.contact_refs.cantilever_drag`;
  its substrate is a :class:`~bristlecrawler.contact.Grooves` whose grooves are 50 mm
  away, so the tip only ever sees the flat land (the same projection as
  :class:`~bristlecrawler.contact.Flat`, one program);
* the bristle tip dragged across the paper's grooves, with the energy balance.
"""

from __future__ import annotations

import functools
import math
from typing import NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from bristlecrawler import fe
from bristlecrawler.contact import STICK, CoulombLaw, Grooves
from bristlecrawler.contact.term import SubstrateContact
from bristlecrawler.fe.motion import SmoothRamp
from bristlecrawler.verification import references
from bristlecrawler.verification.contact_cases import (
    history_at,
    run,
    run_resolving,
    slip_onset,
)
from bristlecrawler.verification.contact_refs import (
    DragResult,
    cantilever_drag,
    inclined_cantilever_compliance,
)

#: Elements of the beam cases (the element is exact for linear statics of a tapered beam
#: up to quadrature, so few are needed).
N_BEAM = 10
#: The paper's bristle (Section 2): Shore A 40 silicone, mm / MPa / tonne.
BRISTLE = fe.TaperedRect(E=1.1, b=30.0, h0=3.0, h1=0.5, rho=1.3e-9, nu=0.45)
BRISTLE_LENGTH = 5.0
#: HHT-alpha of the beam cases, alpha = -0.2 (spectral radius at infinity 0.67). With the
#: default -0.05 (0.90) a tip hitting a groove's wall chatters on the penalty spring: the
#: steps cut at the impact bring the penalty mode to omega dt ~ 10, where -0.05 leaves the
#: bounces ringing; -0.2 damps them within a few steps. Both beam cases use it (one
#: compiled program); the pressed beam is quasi-static, so alpha does not matter there.
BEAM_HHT = fe.Integrator.hht(-0.2)
#: The grooved drag's scheme: BEAM_HHT with the monotone line search (the crawler's). The
#: tip meets each groove's far wall while slipping; Newton, started on the slip tangent
#: (coulomb.STICK_TOL), can cycle between slip in both directions there, which the monotone
#: search breaks and the growth one does not (energy balance 7.4e-4 against 3.1e-3).
DRAG_HHT = fe.Integrator.hht(-0.2, line_search="monotone")


def beam_on_substrate(
    alpha,
    substrate,
    law,
    press,
    press_time,
    drag,
    drag_time,
    blend,
    radius=0.0,
    offset=(0.0, 0.0),
    damping=(0.0, 0.0),
    section=BRISTLE,
    length=BRISTLE_LENGTH,
    n=N_BEAM,
):
    """Cantilever of ``n`` elements clamped at ``alpha`` (rad) from the vertical; its tip
    carries one contact point (``offset`` mm from the tip node, turning with it; a disc of
    ``radius`` mm) that touches the substrate's surface at x = 0 with no force.

    The clamp goes down ``press`` mm in ``press_time`` s (an S-curve) and along x by
    ``drag`` mm (sign = direction) in ``drag_time`` s (constant speed after a start of
    ``blend`` s, and a stop of as long), both from t = 0 with zero velocity
    (:class:`~bristlecrawler.fe.motion.SmoothRamp`: no impulse on the beam at rest); clamp
    rotation fixed. Rayleigh ``damping`` (a0 1/s, a1 s). No gravity.
    Returns (model, term, tip node); the clamp is node 0.
    """
    d = length * np.array([math.sin(alpha), -math.cos(alpha)])
    tip_xy = np.array([0.0, float(substrate.top) + radius]) - np.asarray(offset, float)
    s = fe.Structure()
    clamp = s.node(*(tip_xy - d))
    s.prescribe(clamp, "x", SmoothRamp(drag, drag_time, blend))
    s.prescribe(clamp, "y", SmoothRamp(-press, press_time, 0.5 * press_time))
    s.fix(clamp, "theta")
    nodes = s.chain(clamp, tuple(tip_xy), n, section)
    s.damping(*damping)
    tip = nodes[-1]
    term = SubstrateContact((tip,))
    s.add_term(term, ())
    model = s.build()
    contact = SubstrateContact.params(
        np.asarray(model.params.X),
        (tip,),
        substrate,
        law,
        radius,
        np.reshape(np.asarray(offset, float), (1, 2)),
    )
    return model.with_params(extra=(contact,)), term, tip


def _rest_state(model, term):
    """Dynamic state at rest in the reference configuration, contact points stuck where they
    are. With no load and no contact force there the consistent acceleration is zero (no
    :func:`fe.initial_state` program to compile)."""
    z = jnp.zeros((model.topology.n_nodes, 3))
    hist = (history_at(term, z, model.params.extra[0]),)
    return fe.DynState(jnp.asarray(0.0), jnp.zeros(model.topology.n_red), z, z, z, hist)


def bristle_compliance(alpha: float, section=BRISTLE, length=BRISTLE_LENGTH) -> np.ndarray:
    """Tip compliance (mm/N) of the tapered bristle at ``alpha`` in the (x, y) frame, from
    the closed-form tapered axial and bending compliances (linear theory, no shear)."""
    args = (section.E, section.b, section.h0, section.h1, length)
    fa = references.tapered_axial_compliance(*args)
    fb = references.tapered_bending_compliance(*args)
    # The uniform-beam formula with the equivalent stiffnesses L/EA = fa, L^3/(3 EI) = fb.
    return inclined_cantilever_compliance(length, length**3 / (3 * fb), length / fa, alpha)


# --------------------------------------------------------------------------------------------
# 3. Elastic beam pressed on a flat plane and dragged: stick, then slip
# --------------------------------------------------------------------------------------------

#: Substrate of the pressed beam: a land from x = -49 to 50 mm (grooves far away).
FAR_GROOVES = Grooves(
    width=1.0, depth=0.25, pitch=100.0, phase=50.0, fillet_top=0.1, fillet_bottom=0.1
)


class PressDragRun(NamedTuple):
    """FE pressed-and-dragged beam, extrapolated to a vanishing press, and its reference.

    drag_at_slip: clamp travel at the onset of slip, mm; normal_at_press: normal force when
    the press is complete, before dragging, N; normal_in_slip: normal force in steady slip,
    N; each is the FE value per unit press at ``press`` and ``press / 2`` extrapolated to
    zero press (Richardson, first order), times ``press``. raw: the FE values at
    ``press`` and ``press / 2`` (dicts with the same keys); reference: the linearised
    answer for ``press`` (:class:`DragResult`).
    """

    drag_at_slip: float
    normal_at_press: float
    normal_in_slip: float
    raw: tuple
    reference: DragResult


@functools.lru_cache(maxsize=8)
def _tip_observer(tip):
    @jax.jit
    def observe(st):
        h = st.history[0]
        return st.t, st.u[0, 0], h.state[0], h.p_n[0], h.f_t[0]

    return observe


def _press_and_drag(alpha, mu, press, direction, dt, steps_to_slip):
    """One FE run of the pressed-and-dragged bristle: (drag at slip, normal at press,
    normal in slip) from the FE contact forces."""
    ref = cantilever_drag(bristle_compliance(alpha), press, mu, direction)
    scale = max(ref.normal_at_press, ref.normal_in_slip)
    # penetration and stick drift 1e-4 of the press: the plane is rigid to 1e-4
    law = CoulombLaw.for_reference_load(
        mu, load=scale, design_penetration=1e-4 * press, max_stick_drift=1e-4 * press
    )
    # The drive speed only needs the order of magnitude of the onset (found up to 1.5 x).
    t_slip = steps_to_slip * dt
    t_end, t_press = 1.5 * t_slip, 0.1 * t_slip
    drag = direction * ref.drag_at_slip / t_slip * t_end
    model, term, tip = beam_on_substrate(
        alpha, FAR_GROOVES, law, press, t_press, drag, t_end, blend=t_press
    )
    _, obs = run(
        model, _rest_state(model, term), t_end, dt, _tip_observer(tip), integrator=BEAM_HHT
    )
    t, clamp_x, states, p_n, f_t = (np.array(c) for c in zip(*obs, strict=True))
    h = np.abs(clamp_x)
    h_slip, k = slip_onset(h, f_t, p_n, states, mu)
    # In stick the normal force is affine in the drag: its value at zero drag (press
    # complete) from a fit over the stick steps after the press.
    fit = (t >= t_press) & (states == STICK) & (np.arange(t.size) < max(k, 0))
    n0 = np.polyval(np.polyfit(h[fit], p_n[fit], 1), 0.0) if fit.sum() >= 2 else math.nan
    # steady slip: the last slip step before the clamp slows down (blend at the end)
    slipping = np.flatnonzero((states == 2) & (t <= t_end - t_press))
    n_slip = float(p_n[slipping[-1]]) if slipping.size else math.nan
    return {"drag_at_slip": h_slip, "normal_at_press": float(n0), "normal_in_slip": n_slip}


def pressed_beam_drag_fe(
    alpha: float = math.pi / 6,
    mu: float = 0.65,
    press: float = 0.005,
    direction: float = -1.0,
    dt: float = 2e-3,
    steps_to_slip: int = 100,
) -> PressDragRun:
    """The paper's bristle clamped at ``alpha`` from the vertical, its tip on a flat plane:
    the clamp goes down ``press`` mm, and is dragged along ``direction`` (+1: +x, the way
    the tip leans; -1: the tip trails, the default: pushing the leaning tip wedges it and
    the slip onset becomes sensitive to everything).

    Press and drag start together, the press 10 times faster than the drag needs to reach
    slip, so in stick the contact forces stay well inside the friction cone (linear
    elasticity: the stick state depends only on the current clamp position, and the onset
    is that of press-then-drag). The bristle is light and the drive slow: quasi-static.

    The reference is linear; the FE beam is geometrically nonlinear, and its deviation is
    first order in the press (the tip's rotation under the contact load: 0.6 % at a press of
    0.01 mm, halving with the press). Running ``press`` and ``press / 2`` and
    extrapolating linearly to zero press removes it; what remains is the penalty
    compliance (1e-4 of the press by construction) and second-order terms.
    """
    ref = cantilever_drag(bristle_compliance(alpha), press, mu, direction)
    raw = tuple(
        _press_and_drag(alpha, mu, p, direction, dt, steps_to_slip) for p in (press, 0.5 * press)
    )
    lim = {k: press * (2.0 * raw[1][k] / (0.5 * press) - raw[0][k] / press) for k in raw[0]}
    return PressDragRun(
        lim["drag_at_slip"], lim["normal_at_press"], lim["normal_in_slip"], raw, ref
    )


# --------------------------------------------------------------------------------------------
# 4. A beam tip dragged across grooves: energy balance
# --------------------------------------------------------------------------------------------


class GrooveDragRun(NamedTuple):
    """Beam tip dragged across grooves.

    t: times, s; tip: contact point positions, mm, (n, 2); states: its contact state;
    p_n, f_t: normal and tangential contact force, N; energies: cumulative energies (mJ)
    from t = 0 -- work_in (at the clamp), elastic (beam strain and penalty springs),
    kinetic, friction, damping; grooves_passed: grooves whose both walls the contact
    point's path spans; grooves_entered / climbs: times it went below half the groove
    depth / came back above it; balance_rel_error: max over the run of |work_in -
    (elastic + kinetic + friction + damping)| / max work_in; max_penetration: largest
    penetration, mm (peak normal force / k_n); rejected_steps: steps cut by the driver.
    """

    t: np.ndarray
    tip: np.ndarray
    states: np.ndarray
    p_n: np.ndarray
    f_t: np.ndarray
    energies: dict
    grooves_passed: int
    grooves_entered: int
    climbs: int
    balance_rel_error: float
    max_penetration: float
    rejected_steps: int


@functools.lru_cache(maxsize=8)
def _energy_observer(topo, clamp):
    """Compiled per-state quantities of the energy balance. The contact acts on the tip
    only, so the support reaction at the ``clamp`` node is M a + C v + f_int - f_ext there
    (the force the support applies to the beam)."""
    from bristlecrawler.fe import assembly

    @jax.jit
    def observe(state, params):
        u, v, a = state.u, state.v, state.a
        f_int, damp = assembly.internal_and_damping_force(u, v, params, topo)
        f_ext = assembly.external_force(state.t, 1.0, params, topo)
        full = assembly.mass_times(a, params, topo) + damp + f_int - f_ext
        h = state.history[0]
        law = params.extra[0].law
        penalty = jnp.sum(0.5 * h.p_n**2 / law.k_n + 0.5 * h.f_t**2 / law.k_t)
        return {
            "t": state.t,
            "u": u,
            "reaction": full[clamp],
            "damping_force": damp,
            "elastic": assembly.internal_energy(u, params, topo) + penalty,
            "kinetic": assembly.kinetic_energy(v, params, topo),
            "friction": jnp.sum(h.dissipation),
            "state": h.state[0],
            "p_n": h.p_n[0],
            "f_t": h.f_t[0],
        }

    return observe


def _trapezoid_work(force, u):
    """Cumulative work sum_k (F_k + F_k+1)/2 . (u_k+1 - u_k), mJ, from stacked forces and
    displacements of the same shape (steps first)."""
    f = 0.5 * (force[1:] + force[:-1])
    du = np.diff(u, axis=0)
    inc = np.sum((f * du).reshape(len(du), -1), axis=1)
    return np.concatenate([[0.0], np.cumsum(inc)])


#: The paper's grooves (1 mm wide, 0.25 mm deep, pitch 2 mm assumed) with 0.1 mm fillets,
#: placed so that the tip starts on a land 0.3 mm from the first groove.
DRAG_GROOVES = Grooves(
    width=1.0, depth=0.25, pitch=2.0, phase=0.7, fillet_top=0.1, fillet_bottom=0.1
)


def grooved_drag_fe(
    alpha: float = math.pi / 4,
    mu: float = 0.65,
    press: float = 0.15,
    drag: float = -3.8,
    speed: float = 20.0,
    dt: float = 2e-4,
    zeta: float = 1.0,
    grooves: Grooves = DRAG_GROOVES,
    press_time: float = 0.02,
    radius: float = 0.0,
    max_dp: float | None = 0.005,
    integrator=None,
) -> GrooveDragRun:
    """The paper's bristle at ``alpha``, its tip on a land of ``grooves``, pressed
    ``press`` mm (in ``press_time`` s) and dragged ``drag`` mm at ``speed`` mm/s
    (negative: the tip trails, drops into each groove and climbs its far wall).

    Contact point: the lower corner of the bristle's end face (h1/2 from the axis,
    turning with the tip node, so friction also loads the tip's rotation); with
    ``radius`` > 0 a disc of that radius at the tip node instead. The grooves' corners are
    rounded (0.1 mm fillets). Both choices keep the contact force continuous along the
    path. A disc does not: its arc-length coordinate (that of its closest point on the
    substrate) grows ``r_f / (r_f + r)`` times slower on a fillet of radius r_f and not at
    all on a sharp corner, so its friction force jumps where it reaches a corner; a force
    that jumps within a step kicks the penalty modes, whose energy the scheme dissipates
    whatever the step (with a disc of h1/2 on sharp corners the balance error is 1.5e-3 and
    does not fall with dt). A point at a sharp corner loses contact with a jump as well.

    Mass-proportional Rayleigh damping with ratio ``zeta`` at the first bending frequency
    (estimated from the tip stiffness and a quarter of the bristle's mass). Energies: work
    in at the clamp (support reaction times clamp displacement) and damping (damping force
    times displacement) by the trapezoidal rule over the accepted steps; elastic (beam
    strain and penalty springs), kinetic and friction (exact, from the return mapping) are
    state values. What the balance leaves out: the HHT numerical dissipation, and the
    first-order mismatch between the work of the contact forces over a step and the
    backward-Euler friction dissipation when the normal force changes during slip (see
    :func:`~bristlecrawler.verification.contact_cases.run_resolving`, which bounds the
    normal-force change of a slipping step by ``max_dp`` N; None: the plain driver, which
    cuts steps only when Newton fails). HHT alpha = -0.2 with the monotone line search
    (:data:`DRAG_HHT`) unless ``integrator`` is given.
    """
    law = CoulombLaw.for_reference_load(mu, load=1.0, design_penetration=1e-4)
    # the lower corner of the end face: h1/2 from the axis on the side facing the
    # substrate (-e_b, e_b = (cos alpha, sin alpha) the normal of the axis)
    offset = (
        np.zeros(2)
        if radius > 0
        else -0.5 * BRISTLE.h1 * np.array([math.cos(alpha), math.sin(alpha)])
    )
    k_tip = 1.0 / np.linalg.eigvalsh(bristle_compliance(alpha)).max()
    mass = 0.25 * BRISTLE.rho * BRISTLE.b * 0.5 * (BRISTLE.h0 + BRISTLE.h1) * BRISTLE_LENGTH
    omega = math.sqrt(k_tip / mass)
    blend = 0.01
    t_end = abs(drag) / speed + blend
    model, term, tip = beam_on_substrate(
        alpha,
        grooves,
        law,
        press,
        press_time,
        drag,
        t_end,
        blend,
        radius,
        offset,
        damping=(2.0 * zeta * omega, 0.0),
    )
    state = _rest_state(model, term)
    clamp = 0
    obs, rejected = _drive(model, state, t_end, dt, clamp, max_dp, integrator or DRAG_HHT)
    get = {k: np.array([o[k] for o in obs]) for k in obs[0]}
    u = get["u"]
    energies, err = _drag_energies(get, clamp)
    c, s = np.cos(u[:, tip, 2]), np.sin(u[:, tip, 2])
    point = (
        np.asarray(model.params.X)[tip]
        + u[:, tip, :2]
        + np.column_stack([c * offset[0] - s * offset[1], s * offset[0] + c * offset[1]])
    )
    passed, entered, climbs = _groove_passages(point, grooves, radius)
    pen = float(np.max(get["p_n"]) / float(law.k_n))
    return GrooveDragRun(
        get["t"],
        point,
        get["state"],
        get["p_n"],
        get["f_t"],
        energies,
        passed,
        entered,
        climbs,
        err,
        pen,
        rejected,
    )


def _drive(model, state, t_end, dt, clamp, max_dp, integrator):
    """The records of a drag from ``state`` to ``t_end`` (the first one at ``state``) and
    the rejected steps: :func:`run_resolving` bounding the normal-force change of a
    slipping step by ``max_dp`` N, or the plain driver for None."""
    obs_fn = _energy_observer(model.topology, clamp)
    params = model.params
    first = obs_fn(state, params)

    def observe(st):
        return obs_fn(st, params)

    if max_dp is None:
        res, obs = run(model, state, t_end, dt, observe, integrator=integrator)
    else:
        res = run_resolving(model, state, t_end, dt, observe, max_dp, integrator=integrator)
        obs = res.observed
    return [jax.device_get(first), *obs], res.rejected


def _drag_energies(get, clamp):
    """Energies of a drag's records (work in at the clamp and damping by the trapezoidal
    rule, the others state values, all from zero) and the balance error relative to the
    largest work."""
    u = get["u"]
    work = _trapezoid_work(get["reaction"][:, :2], u[:, clamp, :2])
    damping = _trapezoid_work(get["damping_force"], u)
    energies = {
        "work_in": work,
        "elastic": get["elastic"] - get["elastic"][0],
        "kinetic": get["kinetic"] - get["kinetic"][0],
        "friction": get["friction"] - get["friction"][0],
        "damping": damping,
    }
    rest = energies["elastic"] + energies["kinetic"] + energies["friction"] + damping
    return energies, float(np.max(np.abs(work - rest)) / np.max(np.abs(work)))


def _groove_passages(point, grooves, radius):
    """(grooves passed over, drops into a groove, climbs out) of a contact point's path
    (k, 2) mm: below half the depth counts as in a groove."""
    top, depth = float(grooves.top), float(grooves.depth)
    below = point[:, 1] - radius < top - 0.5 * depth
    entered = int(np.sum(below[1:] & ~below[:-1]))
    climbs = int(np.sum(~below[1:] & below[:-1]))
    lo, hi = point[:, 0].min(), point[:, 0].max()
    pitch, phase, width = float(grooves.pitch), float(grooves.phase), float(grooves.width)
    k = np.arange(math.floor((lo - phase) / pitch), math.ceil((hi - phase) / pitch) + 1)
    left = phase + k * pitch
    passed = int(np.sum((left > lo) & (left + width < hi)))
    return passed, entered, climbs


__all__ = [
    "BEAM_HHT",
    "BRISTLE",
    "DRAG_GROOVES",
    "DRAG_HHT",
    "FAR_GROOVES",
    "GrooveDragRun",
    "PressDragRun",
    "beam_on_substrate",
    "bristle_compliance",
    "grooved_drag_fe",
    "pressed_beam_drag_fe",
]
