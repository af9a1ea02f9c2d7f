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
)


@dataclass(frozen=True)
class SlideOptions:
    """The slide corrector.

    Attributes:
        du_max: largest slide of a tip in one iteration, mm.
        tol: force beyond the Coulomb cone below which a tip sticks, N.
        iterations: corrector iterations at most per step of s.
        stiffness: first guess of a sliding tip's force drop per mm, N/mm.
    """

    du_max: float = 0.01
    tol: float = 1e-6
    iterations: int = 4000
    stiffness: float = 0.5


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
    """Running sums over a run, per design (mJ): the actuator's work, the dissipation,
    its Coulomb part mu N |dT| and the work sum f ds of the actuator's force."""

    work: np.ndarray
    dissipation: np.ndarray
    coulomb: np.ndarray
    lifts: np.ndarray
    unconverged: np.ndarray

    @classmethod
    def zeros(cls, n: int) -> Tally:
        z = np.zeros(n)
        return cls(z.copy(), z.copy(), z.copy(), np.zeros(n, int), np.zeros(n, int))


def cone_excess(bodies: Bodies, contacts: Contacts, lam, u):
    """Each tip's force beyond its Coulomb cone (N, (D, B); <= 0 sticks), the direction it
    slides (+-1 along the path) and its normal force (N). The substrate's force on a tip
    is -lambda."""
    _, t, n = contacts.frame(u)
    normal = -np.sum(lam * n, -1)
    tangential = -np.sum(lam * t, -1)
    excess = np.abs(tangential) - contacts.mu[:, None] * np.maximum(normal, 0.0)
    excess = np.where(bodies.on, excess, -1.0)
    return excess, -np.sign(tangential), normal


def predict(bodies, contacts, pose, u, s_old, s_new, tally: Tally, newton=NewtonOptions()):
    """The stick predictor: the equilibrium at ``s_new`` with the tips held. ``pose`` is
    (q, phi, lambda); returns the new one."""
    tips, _, _ = contacts.frame(u)
    q, phi, lam = pose
    before = potential(bodies, q, phi, s_old)
    q, phi, lam, ok = equilibrium(bodies, q, phi, lam, tips, s_new, newton)
    tally.work += potential(bodies, q, phi, s_new) - before
    tally.unconverged += ~ok
    return q, phi, lam


def _slide_step(excess, dirn, last_ex, last_du, opts):
    """How far each tip beyond its cone slides next: a secant step on its excess force
    along the path, at most ``du_max`` (the full step where the excess does not fall)."""
    moved = last_du > 0
    secant = (last_ex - excess) / np.where(moved, last_du, 1.0)
    slope = np.where(moved, secant, opts.stiffness)
    slope = np.where(slope > 0.05 * opts.stiffness, slope, 0.0)
    du = np.where(slope > 0, excess / np.where(slope > 0, slope, 1.0), opts.du_max)
    du = np.clip(du, 1e-9, opts.du_max)
    return np.where(excess > opts.tol, du, 0.0)


def correct(bodies, contacts, pose, u, s, tally: Tally, opts=SlideOptions(), newton=NewtonOptions()):
    """The slide corrector at frozen ``s``: returns (pose, u)."""
    q, phi, lam = pose
    start = potential(bodies, q, phi, s)
    excess, dirn, normal = cone_excess(bodies, contacts, lam, u)
    rows = np.arange(len(q))
    last_du = np.zeros(u.shape)
    last_ex = excess.copy()
    for _ in range(opts.iterations):
        live = (excess > opts.tol).any(axis=1)
        if not live.any():
            break
        act = rows[live]
        du = _slide_step(excess[act], dirn[act], last_ex[act], last_du[act], opts)
        nf = normal[act]
        tally.coulomb[act] += np.sum(contacts.mu[act][:, None] * np.maximum(nf, 0.0) * du, 1)
        tally.lifts[act] += np.sum((du > 0) & (nf < 0), axis=1)
        u = u.copy()
        u[act] += dirn[act] * du
        ba, ca = bodies.take(act), contacts.take(act)
        tips_a, _, _ = ca.frame(u[act])
        qa, pa, la, ok = equilibrium(ba, q[act], phi[act], lam[act], tips_a, s[act], newton)
        q, phi, lam = q.copy(), phi.copy(), lam.copy()
        q[act], phi[act], lam[act] = qa, pa, la
        tally.unconverged[act] += ~ok
        last_ex[act], last_du[act] = excess[act], du
        excess[act], dirn[act], normal[act] = cone_excess(ba, ca, la, u[act])
    tally.dissipation += start - potential(bodies, q, phi, s)
    return (q, phi, lam), u
