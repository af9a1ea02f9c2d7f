"""Quasi-static, rate-independent crawling of a batch of designs: stick predictor, slide
corrector.

The actuator's shortenings s are played as a sequence of values (time never enters: the
result depends on the values s passes through, not on how fast). From one value to the
next:

1. **Stick predictor.** The tips are held where they are and the body moves to its
   equilibrium under the new s (:func:`.body.equilibrium`). With the tips held nothing
   dissipates, so the actuator's work over the step is the rise of the potential energy
   Pi = E_el + E_g, exactly.
2. **Slide corrector.** At the new s, each tip whose force R (from the substrate) leaves
   the Coulomb cone of its contact, |R . t| > mu R . n, slides along its path in the
   direction of -R . t, the body following in equilibrium, until its force is back on the
   cone (a secant search along the path, in increments of at most ``du_max``). A tip that
   reaches a land edge or a groove wall stops where the wall's normal takes its force into
   the cone; one whose resistance falls as it goes (a tip climbing out of a groove past the
   steepest point of its wall) runs on at frozen s to its next stop: a snap. The actuator
   does no work at frozen s, so the fall of Pi over the corrector is the energy dissipated,
   sliding and snaps together, exactly.

So W = (E_el + E_g)(end) - (E_el + E_g)(start) + D holds by construction step by step;
what it leaves to check is that each step's W is the integral of the actuator's force
(:func:`.body.actuator_forces`), which the tests do. Units: mm, N, mJ.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from bristlecrawler.reduced.bristled.body import (
    Bodies,
    NewtonOptions,
    actuator_forces,
    equilibrium,
    potential,
    tips_of,
)
from bristlecrawler.reduced.bristled.slide import solve_slides


@dataclass(frozen=True)
class SlideOptions:
    """The slide corrector.

    Attributes:
        du_max: largest first slide of a tip in a snap's run, mm.
        du_run: largest slide of a tip in one iteration of a snap's run, mm.
        du_cap: largest slide of a tip in one Newton iteration of the joint slide solve, mm.
        solve_iterations: Newton iterations of the joint slide solve at most (a solve that
            needs more is taken for a snap, and its tips run on).
        tol: force beyond the Coulomb cone below which a tip sticks, N.
        iterations: corrector iterations at most per step of s (a step that needs more
            is counted as stalled, and its design fails).
        stiffness: first guess of a sliding tip's force drop per mm, N/mm.
        near: a tip within this force of its cone's edge (N) may slide with the others.
    """

    du_max: float = 0.01
    du_run: float = 0.05
    du_cap: float = 0.1
    solve_iterations: int = 12
    tol: float = 1e-6
    iterations: int = 400
    stiffness: float = 0.5
    near: float = 1e-3


@dataclass(frozen=True)
class Contacts:
    """The substrate under each design: ``paths`` a :class:`.path.PathTable`, ``which``
    (D,) the path of each design, ``mu`` (D,) Coulomb's coefficient."""

    paths: object
    which: np.ndarray
    mu: np.ndarray

    def take(self, rows) -> Contacts:
        return Contacts(self.paths, self.which[rows], self.mu[rows])

    def frame(self, u):
        return self.paths.frame(self.which[:, None], u)

    def derivatives(self, u):
        return self.paths.derivatives(self.which[:, None], u)


@dataclass
class Tally:
    """Running sums over a run, per design: the actuator's work, the dissipation and its
    Coulomb part mu N |dT| (mJ); tips lifting off or touching down, equilibrium solves
    that did not converge, and steps whose slides did not settle (counts); the actuators'
    force integrated over their shortening by the trapezoid rule (mJ, a check of the
    work)."""

    work: np.ndarray
    dissipation: np.ndarray
    coulomb: np.ndarray
    lifts: np.ndarray
    unconverged: np.ndarray
    stalled: np.ndarray
    force_work: np.ndarray

    @classmethod
    def zeros(cls, n: int) -> Tally:
        z = np.zeros(n)
        i = np.zeros(n, int)
        return cls(z.copy(), z.copy(), z.copy(), i.copy(), i.copy(), i.copy(), z.copy())

    def add(self, rows, other: Tally) -> None:
        """Add ``other``'s sums (over the designs ``rows``) to these."""
        for f in dataclasses.fields(self):
            getattr(self, f.name)[rows] += getattr(other, f.name)

    def take(self, rows) -> Tally:
        return Tally(*(getattr(self, f.name)[rows] for f in dataclasses.fields(self)))


def cone_excess(bodies: Bodies, contacts: Contacts, lam, u, held):
    """Each held tip's force beyond its Coulomb cone (N, (D, B); <= 0 sticks, -1 for a
    free tip), the direction it slides (+-1 along the path) and its normal force (N). The
    substrate's force on a tip is -lambda."""
    _, t, n = contacts.frame(u)
    normal = -np.sum(lam * n, -1)
    tangential = -np.sum(lam * t, -1)
    excess = np.abs(tangential) - contacts.mu[:, None] * np.maximum(normal, 0.0)
    excess = np.where(bodies.on & held, excess, -1.0)
    return excess, -np.sign(tangential), normal


def predict(
    bodies, contacts, pose, u, s_old, s_new, tally: Tally, carry=None, opts=None, newton=None
):
    """The predictor: the equilibrium at ``s_new`` with the tips held, except those in
    ``carry`` = (sliding (D, B), direction (D, B)), the tips that were sliding at
    ``s_old``, which go on sliding on their cones' edges (:func:`.slide.solve_slides`; one that
    would go backwards sticks). ``pose`` is (q, phi, lambda, held); returns (pose, u).

    The actuator's work over the step is the rise of Pi = E_el + E_g plus what the
    carried slides dissipated, mu N |du| (N by the trapezoid rule over the step). Also
    returns which designs' carried slides found no stop (a snap within the step)."""
    opts, newton = opts or SlideOptions(), newton or NewtonOptions()
    q, phi, lam, held = pose
    before = potential(bodies, q, phi, s_old)
    _, _, n_old = cone_excess(bodies, contacts, lam, u, held)
    new_pose, new_u = pose, u
    done = np.zeros(len(u), bool)
    snapped = np.zeros(len(u), bool)
    if carry is not None and carry[0].any():
        rows = np.flatnonzero(carry[0].any(axis=1))
        p_c, u_c, ok_c = solve_slides(
            bodies.take(rows),
            contacts.take(rows),
            tuple(a[rows] for a in pose),
            u[rows],
            s_new[rows],
            np.zeros_like(carry[0][rows]),
            carry[0][rows],
            carry[1][rows],
            opts.du_cap,
            dataclasses.replace(newton, iterations=opts.solve_iterations),
        )
        new_pose = tuple(a.copy() for a in pose)
        for a, b in zip(new_pose, p_c, strict=True):
            a[rows] = np.where(_col(ok_c, b), b, a[rows])
        new_u = u.copy()
        new_u[rows] = np.where(ok_c[:, None], u_c, u[rows])
        done[rows] = ok_c
        snapped[rows] = ~ok_c
    rest = np.flatnonzero(~done)
    if rest.size:
        tips, _, _ = contacts.take(rest).frame(u[rest])
        q_r, phi_r, lam_r, ok = equilibrium(
            bodies.take(rest), q[rest], phi[rest], lam[rest], tips, s_new[rest], held[rest], newton
        )
        new_pose = tuple(a.copy() for a in new_pose)
        new_pose[0][rest], new_pose[1][rest], new_pose[2][rest] = q_r, phi_r, lam_r
        tally.unconverged[rest] += ~ok
    q, phi, lam, _ = new_pose
    _, _, n_new = cone_excess(bodies, contacts, lam, new_u, held)
    normal = 0.5 * (np.maximum(n_old, 0.0) + np.maximum(n_new, 0.0))
    slid = np.sum(contacts.mu[:, None] * normal * np.abs(new_u - u), axis=1)
    tally.work += potential(bodies, q, phi, s_new) - before + slid
    tally.dissipation += slid
    tally.coulomb += slid
    return new_pose, new_u, snapped


def step(bodies, contacts, state, s_old, s_new, tally: Tally, opts, newton, refine: int):
    """One step of the shortenings from ``s_old`` to ``s_new`` (D, B-1) mm: the predictor,
    then the corrector. ``state`` is (pose, u, carry); returns the new one. A design whose
    carried slides snap within the step plays it again in ``refine`` smaller steps: the
    held predictor's overshoot, released by the corrector, shrinks with the step."""
    pose, u, carry = state
    trial = Tally.zeros(len(u))
    f_old = actuator_forces(bodies, pose[0], pose[2], s_old)
    pose, u_new, snapped = predict(
        bodies, contacts, pose, u, s_old, s_new, trial, carry, opts, newton
    )
    f_new = actuator_forces(bodies, pose[0], pose[2], s_new)
    trial.force_work += np.sum(0.5 * (f_old + f_new) * (s_new - s_old), axis=1)
    pose, u_new = correct(bodies, contacts, pose, u_new, s_new, trial, opts, newton)
    carried = sliding_tips(bodies, contacts, pose, u, u_new, opts)
    if carry is not None:
        # Where s stood still nothing moved, and what was sliding still is.
        still = np.all(s_new == s_old, axis=1)[:, None]
        carried = tuple(np.where(still, a, b) for a, b in zip(carry, carried, strict=True))
    new = (pose, u_new, carried)
    redo = np.flatnonzero(snapped) if refine > 1 else np.zeros(0, int)
    keep = np.ones(len(u), bool)
    keep[redo] = False
    tally.add(keep, trial.take(keep))
    if redo.size:
        sub = _rows(state, redo)
        sub_tally = Tally.zeros(redo.size)
        b, c = bodies.take(redo), contacts.take(redo)
        for k in range(refine):
            a0 = s_old[redo] + (s_new[redo] - s_old[redo]) * (k / refine)
            a1 = s_old[redo] + (s_new[redo] - s_old[redo]) * ((k + 1) / refine)
            sub = step(b, c, sub, a0, a1, sub_tally, opts, newton, 1)
        tally.add(redo, sub_tally)
        new = _put(new, redo, sub)
    return new


def sliding_tips(bodies, contacts, pose, u_old, u_new, opts):
    """The tips that slid over the last step and are still on their cones' edges, and the
    way they slid: the predictor carries them on into the next step."""
    excess, dirn, _ = cone_excess(bodies, contacts, pose[2], u_new, pose[3])
    moved = np.abs(u_new - u_old) > 1e-9
    return moved & (excess > -opts.near), dirn


def _rows(state, rows):
    pose, u, carry = state
    return (
        tuple(a[rows] for a in pose),
        u[rows],
        None if carry is None else tuple(a[rows] for a in carry),
    )


def _put(state, rows, sub):
    pose, u, carry = state
    pose = tuple(a.copy() for a in pose)
    for a, b in zip(pose, sub[0], strict=True):
        a[rows] = b
    u = u.copy()
    u[rows] = sub[1]
    carry = tuple(a.copy() for a in carry)
    for a, b in zip(carry, sub[2], strict=True):
        a[rows] = b
    return pose, u, carry


def _slide_step(excess, last_ex, last_du, opts):
    """How far each tip beyond its cone slides next: a secant step on its excess force
    along the path, at most ``du_max`` at first and at most twice the last step after that,
    up to ``du_run`` (a long snap runs on in growing steps)."""
    moved = last_du > 0
    secant = (last_ex - excess) / np.where(moved, last_du, 1.0)
    slope = np.where(moved, secant, opts.stiffness)
    slope = np.where(slope > 0.05 * opts.stiffness, slope, 0.0)
    du = np.where(slope > 0, excess / np.where(slope > 0, slope, 1.0), opts.du_max)
    cap = np.clip(2.0 * last_du, opts.du_max, opts.du_run)
    du = np.clip(du, 1e-9, cap)
    return np.where(excess > opts.tol, du, 0.0)


def _lift_and_touch(bodies, contacts, pose, u, s, opts):
    """A tip pulled upwards (the substrate's force on it pointing down by more than
    ``tol``) that does not slide comes free, the one pulled hardest of each design at a
    time; free tips whose rest place is below the substrate touch down where they are.
    (A tip pushed away from a groove's wall but not up slides along the corner's bend
    instead.) Returns (held, u, changed (D,) bool)."""
    q, phi, lam, held = pose
    excess, _, _ = cone_excess(bodies, contacts, lam, u, held)
    pull = np.where(held & (excess <= opts.tol), lam[..., 1], -np.inf)
    worst = np.argmax(pull, axis=1)
    lift = np.zeros_like(held)
    lift[np.arange(len(q)), worst] = pull[np.arange(len(q)), worst] > opts.tol
    free = bodies.on & ~held & ~lift
    tips = tips_of(bodies, q, phi, s)
    which = np.broadcast_to(contacts.which[:, None], u.shape)
    below = free & (tips[..., 1] < contacts.paths.height_at(which, tips[..., 0]))
    u = np.where(below, contacts.paths.arc_at(which, tips[..., 0]), u)
    held = (held & ~lift) | below
    return held, u, (lift | below).any(axis=1)


def _where(mask, new, old):
    """``new`` where ``mask`` (D,), else ``old``: tuples of arrays over designs."""
    return tuple(np.where(_col(mask, a), b, a) for a, b in zip(old, new, strict=True))


def _col(mask, a):
    return mask.reshape(mask.shape + (1,) * (np.ndim(a) - 1))


def _run_on(bodies, contacts, pose, u, s, du, dirn, newton):
    """The tips moved by ``du`` (mm, >= 0) in the directions ``dirn`` and the body in
    equilibrium with them held there: (pose, u, converged)."""
    q, phi, lam, held = pose
    u = u + dirn * du
    tips, _, _ = contacts.frame(u)
    q, phi, lam, ok = equilibrium(bodies, q, phi, lam, tips, s, held, newton)
    return (q, phi, lam, held), u, ok


def correct(bodies, contacts, pose, u, s, tally: Tally, opts=None, newton=None):
    """The slide corrector at frozen ``s``: returns (pose, u).

    Each iteration finds the stops of every tip beyond its cone together
    (:func:`.slide.solve_slides`); where there is none nearby (a snap: the resistance
    falls as the tip goes) the tips run on in growing steps (``du_max`` to ``du_run``)
    until their stop is within a Newton iteration's reach."""
    opts, newton = opts or SlideOptions(), newton or NewtonOptions()
    start = potential(bodies, pose[0], pose[1], s)
    rows = np.arange(len(u))
    last_du = np.zeros(u.shape)
    last_ex = np.zeros(u.shape)
    snapping = np.zeros(len(u), bool)
    live = np.zeros(len(u), bool)
    for _ in range(opts.iterations):
        held, u, changed = _lift_and_touch(bodies, contacts, pose, u, s, opts)
        pose = (*pose[:3], held)
        excess, dirn, normal = cone_excess(bodies, contacts, pose[2], u, held)
        live = (excess > opts.tol).any(axis=1) | changed
        if not live.any():
            break
        # A snapping tip is solved for again once its resistance rises enough that, by the
        # secant, its stop is within one Newton iteration's reach.
        slope = (last_ex - excess) / np.where(last_du > 0, last_du, 1.0)
        near_stop = (last_du > 0) & (slope > 0) & (excess < slope * opts.du_cap)
        snapping &= ~near_stop.any(axis=1)
        du = _slide_step(excess, last_ex, last_du, opts)
        du = np.where(changed[:, None], 0.0, du)
        new_pose, new_u = pose, u
        solved = np.zeros(len(u), bool)
        trial = rows[live & ~changed & ~snapping]
        if trial.size:
            p_t, u_t, ok_t = solve_slides(
                bodies.take(trial),
                contacts.take(trial),
                tuple(a[trial] for a in pose),
                u[trial],
                s[trial],
                excess[trial] > opts.tol,
                excess[trial] > -opts.near,
                dirn[trial],
                opts.du_cap,
                dataclasses.replace(newton, iterations=opts.solve_iterations),
            )
            solved[trial] = ok_t
            snapping[trial] |= ~ok_t
            new_pose = tuple(a.copy() for a in pose)
            for a, b in zip(new_pose, p_t, strict=True):
                a[trial] = np.where(_col(ok_t, b), b, a[trial])
            new_u = u.copy()
            new_u[trial] = np.where(ok_t[:, None], u_t, u[trial])
            du[trial] = np.where(ok_t[:, None], np.abs(u_t - u[trial]), du[trial])
        rest = rows[live & ~solved]
        if rest.size:
            p_r, u_r, ok_r = _run_on(
                bodies.take(rest),
                contacts.take(rest),
                tuple(a[rest] for a in pose),
                u[rest],
                s[rest],
                du[rest],
                dirn[rest],
                newton,
            )
            new_pose = tuple(a.copy() for a in new_pose)
            for a, b in zip(new_pose, p_r, strict=True):
                a[rest] = b
            new_u = new_u.copy()
            new_u[rest] = u_r
            tally.unconverged[rest] += ~ok_r
        tally.coulomb += np.sum(contacts.mu[:, None] * np.maximum(normal, 0.0) * du, 1) * live
        tally.lifts += changed
        pose, u = new_pose, new_u
        last_ex = np.where(live[:, None], excess, last_ex)
        last_du = np.where(live[:, None], du, last_du)
    else:
        tally.stalled += live
    tally.dissipation += start - potential(bodies, pose[0], pose[1], s)
    return pose, u
