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

from dataclasses import dataclass

import numpy as np

from bristlecrawler.reduced.bristled.body import (
    Bodies,
    NewtonOptions,
    equilibrium,
    potential,
    tips_of,
)


@dataclass(frozen=True)
class SlideOptions:
    """The slide corrector.

    Attributes:
        du_max: largest slide of a tip in one iteration, mm.
        tol: force beyond the Coulomb cone below which a tip sticks, N.
        iterations: corrector iterations at most per step of s (a step that needs more
            is counted as stalled, and its design fails).
        stiffness: first guess of a sliding tip's force drop per mm, N/mm.
        near: a tip within this force of its cone's edge (N) may slide with the others.
    """

    du_max: float = 0.01
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


@dataclass
class Tally:
    """Running sums over a run, per design: the actuator's work, the dissipation and its
    Coulomb part mu N |dT| (mJ); tips lifting off or touching down, equilibrium solves
    that did not converge, and steps whose slides did not settle (counts)."""

    work: np.ndarray
    dissipation: np.ndarray
    coulomb: np.ndarray
    lifts: np.ndarray
    unconverged: np.ndarray
    stalled: np.ndarray

    @classmethod
    def zeros(cls, n: int) -> Tally:
        z = np.zeros(n)
        i = np.zeros(n, int)
        return cls(z.copy(), z.copy(), z.copy(), i.copy(), i.copy(), i.copy())


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


def predict(bodies, contacts, pose, u, s_old, s_new, tally: Tally, newton=None):
    """The stick predictor: the equilibrium at ``s_new`` with the tips held. ``pose`` is
    (q, phi, lambda, held); returns the new one."""
    newton = newton or NewtonOptions()
    tips, _, _ = contacts.frame(u)
    q, phi, lam, held = pose
    before = potential(bodies, q, phi, s_old)
    q, phi, lam, ok = equilibrium(bodies, q, phi, lam, tips, s_new, held, newton)
    tally.work += potential(bodies, q, phi, s_new) - before
    tally.unconverged += ~ok
    return q, phi, lam, held


def _slide_step(excess, last_ex, last_du, opts):
    """How far each tip beyond its cone slides next: a secant step on its excess force
    along the path, at most ``du_max`` (the full step where the excess does not fall)."""
    moved = last_du > 0
    secant = (last_ex - excess) / np.where(moved, last_du, 1.0)
    slope = np.where(moved, secant, opts.stiffness)
    slope = np.where(slope > 0.05 * opts.stiffness, slope, 0.0)
    du = np.where(slope > 0, excess / np.where(slope > 0, slope, 1.0), opts.du_max)
    du = np.clip(du, 1e-9, opts.du_max)
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


def _coupled_step(bodies, contacts, pose, u, s, excess, dirn, fallback, opts, newton):
    """Slides that bring every tip beyond its cone back onto it together, to first order:
    the tips' excess forces' sensitivities to each other's slides by finite differences
    (a tip's slide loads the others through the stiff body), then the linear solve; where
    that asks for a slide backwards or beyond ``du_max`` (a snap), ``fallback``."""
    q, phi, lam, held = pose
    h = 1e-6
    n_b = u.shape[1]
    # Tips on their cones' edge may slide too, as the others' slides load them.
    moving = excess > -opts.near
    jac = np.zeros((*u.shape, n_b))
    for j in range(n_b):
        if not moving[:, j].any():
            continue
        up = u.copy()
        up[:, j] += dirn[:, j] * h
        tips, _, _ = contacts.frame(up)
        _, _, lj, _ = equilibrium(bodies, q, phi, lam, tips, s, held, newton)
        ex_j, _, _ = cone_excess(bodies, contacts, lj, up, held)
        jac[:, :, j] = (ex_j - excess) / h
    # Tips the others' slides bring back within their cones stay (an active set).
    for _ in range(n_b):
        both = moving[:, :, None] & moving[:, None, :]
        m = np.where(both, jac, 0.0) + np.where(moving, 0.0, 1.0)[:, :, None] * np.eye(n_b)
        ok = np.abs(np.linalg.det(m)) > 1e-300
        m[~ok] = np.eye(n_b)
        du = np.linalg.solve(m, np.where(moving, -excess, 0.0)[..., None])[..., 0]
        back = moving & (du <= 0)
        if not back.any():
            break
        moving = moving & ~back
    du = np.where(moving, du, 0.0)
    # A slide longer than du_max / 5 (the linear model's reach) is cut, all tips in proportion.
    cap = 0.2 * opts.du_max
    du = du * np.minimum(1.0, cap / np.maximum(du.max(axis=1), 1e-300))[:, None]
    good = ok & moving.any(axis=1) & np.all(np.isfinite(du), axis=1)
    return np.where(good[:, None], du, fallback)


def correct(bodies, contacts, pose, u, s, tally: Tally, opts=None, newton=None):
    """The slide corrector at frozen ``s``: returns (pose, u)."""
    opts, newton = opts or SlideOptions(), newton or NewtonOptions()
    q, phi, lam, held = pose
    start = potential(bodies, q, phi, s)
    rows = np.arange(len(q))
    last_du = np.zeros(u.shape)
    last_ex = np.zeros(u.shape)
    live = np.zeros(len(q), bool)
    for _ in range(opts.iterations):
        held, u, changed = _lift_and_touch(bodies, contacts, (q, phi, lam, held), u, s, opts)
        excess, dirn, normal = cone_excess(bodies, contacts, lam, u, held)
        slide = excess > opts.tol
        live = slide.any(axis=1) | changed
        if not live.any():
            break
        act = rows[live]
        ba, ca = bodies.take(act), contacts.take(act)
        du = _slide_step(excess[act], last_ex[act], last_du[act], opts)
        # Three or more tips hold the body stiffly: their slides are solved together.
        many = np.flatnonzero(bodies.on[act].sum(axis=1) >= 3)
        if many.size:
            bm, cm, rows_m = ba.take(many), ca.take(many), act[many]
            pose_m = (q[rows_m], phi[rows_m], lam[rows_m], held[rows_m])
            du[many] = _coupled_step(
                bm,
                cm,
                pose_m,
                u[rows_m],
                s[rows_m],
                excess[rows_m],
                dirn[rows_m],
                du[many],
                opts,
                newton,
            )
        du = np.where(changed[act][:, None], 0.0, du)
        tally.coulomb[act] += np.sum(
            contacts.mu[act][:, None] * np.maximum(normal[act], 0.0) * du, 1
        )
        tally.lifts[act] += changed[act]
        u = u.copy()
        u[act] += dirn[act] * du
        tips_a, _, _ = ca.frame(u[act])
        qa, pa, la, ok = equilibrium(
            ba, q[act], phi[act], lam[act], tips_a, s[act], held[act], newton
        )
        q, phi, lam = q.copy(), phi.copy(), lam.copy()
        q[act], phi[act], lam[act] = qa, pa, la
        tally.unconverged[act] += ~ok
        last_ex[act], last_du[act] = excess[act], du
    else:
        tally.stalled += live
    tally.dissipation += start - potential(bodies, q, phi, s)
    return (q, phi, lam, held), u
