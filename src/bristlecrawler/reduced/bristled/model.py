"""The bristled crawler: designs in, advance and work out, for a whole batch at once.

A :class:`BristledDesign` is one crawler: its bristles (each a :class:`~.rod.TaperedBristle`
at a place along the body), the body (mass, links, whether it may pitch), the substrate
(:class:`~.path.GroovedSurface` or :class:`~.path.PolylineSurface`), Coulomb's mu and the
breathing stroke s~. :func:`run` plays ``cycles`` strokes on a batch of them:

1. **Gravity.** The body is put down level with each tip at its unloaded place on the
   substrate; the body settles in equilibrium with the tips held, then the tips slide where
   their forces leave the Coulomb cone (as the FE crawler's gravity step).
2. **Strokes.** Every segment shortens from 0 to s~ and back (the breathing gait) in steps
   of at most ``ds`` mm, each a stick predictor and a slide corrector (:mod:`.crawl`).

The rods are calibrated once per bristle geometry and the tip paths once per substrate and
tip radius (both cached in the process). Units: mm, N, s, tonne, mJ.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, field

import numpy as np

from bristlecrawler.errors import InputError
from bristlecrawler.reduced.bristled.body import (
    Bodies,
    NewtonOptions,
    energy,
    equilibrium,
)
from bristlecrawler.reduced.bristled.crawl import (
    Contacts,
    SlideOptions,
    Tally,
    correct,
    step,
)
from bristlecrawler.reduced.bristled.path import (
    GroovedSurface,
    PathTable,
    TipPath,
    bristle_end_shape,
)
from bristlecrawler.reduced.bristled.rod import (
    Chain,
    TaperedBristle,
    chain_angles_under_force,
    chain_fields,
    chain_tip,
)

#: The model's name in outputs.
MODEL_NAME = "bristled"


@dataclass(frozen=True)
class BristledDesign:
    """One crawler for the bristled model.

    Attributes:
        bristles: one :class:`TaperedBristle` per bristle, rear to front.
        places: where each bristle's body node is along the body, mm (the first at 0).
        body_mass: the body's mass, t (shared equally by the body nodes).
        link_length: the rigid links from the body nodes to the clamps, mm.
        free_pitch: the body may pitch.
        surface: the substrate.
        mu: Coulomb's friction coefficient, -.
        s_max: each segment's peak shortening s~, mm.
        gravity: mm/s^2.
        bristle_density: t/mm^3 (the bristles' own weight, carried at their nodes).
        start: x of the rear body node before the gravity step, mm.
    """

    bristles: tuple[TaperedBristle, ...] = (TaperedBristle(), TaperedBristle())
    places: tuple[float, ...] = (0.0, 100.0)
    body_mass: float = 5.5e-5
    link_length: float = 10.0
    free_pitch: bool = True
    surface: object = field(default_factory=GroovedSurface)
    mu: float = 0.65
    s_max: float = 20.0
    gravity: float = 9810.0
    bristle_density: float = 1.3e-9
    start: float = 0.0

    def check(self) -> None:
        if len(self.bristles) < 2 or len(self.places) != len(self.bristles):
            raise InputError("a bristled crawler needs >= 2 bristles, each with a place")
        if not np.all(np.diff(self.places) > 0):
            raise InputError(f"bristle places must increase, got {self.places}")
        if not (self.s_max > 0 and self.body_mass > 0 and self.mu >= 0):
            raise InputError("s_max and body_mass must be > 0 and mu >= 0")

    @classmethod
    def uniform(cls, count: int = 2, length: float = 100.0, **changes) -> BristledDesign:
        """``count`` bristles of ``bristle`` (a :class:`TaperedBristle`, default the
        paper's) spread evenly over ``length`` mm; other fields by keyword."""
        b = changes.pop("bristle", TaperedBristle())
        places = tuple(float(x) for x in np.linspace(0.0, length, count))
        return cls(bristles=(b,) * count, places=places, **changes)


@functools.lru_cache(maxsize=256)
def chain_of(bristle: TaperedBristle) -> Chain:
    """The calibrated rod of a bristle geometry (cached)."""
    return Chain.of(bristle)


@functools.lru_cache(maxsize=64)
def path_of(surface, bristle: TaperedBristle, load: float, samples: int = 2048) -> TipPath:
    """The tip path of ``bristle`` over ``surface`` (cached): its last quarter length's
    outline (faces and flat end) held at the angle its rod takes under the vertical tip
    ``load`` (N; the weight on its node)."""
    chain = chain_of(bristle)
    p = {k: np.asarray(v) for k, v in chain_fields([chain]).items()}
    phi = chain_angles_under_force(np.array([[0.0, load]]), p)
    angle = chain.theta_r + float(phi[0, 0] + phi[1, 0])
    taper = 0.5 * (bristle.thickness_clamp - bristle.thickness_tip) / bristle.length
    shape = bristle_end_shape(bristle.thickness_tip, taper, angle, 0.25 * bristle.length)
    return TipPath.over(surface.outline(), shape, samples)


@dataclass(frozen=True)
class RunOptions:
    """How a batch is run.

    Attributes:
        ds: largest step of the shortening, mm.
        refine: a step in which a sliding tip snaps is played again in this many steps.
        newton: the body's equilibrium solve. slide: the slide corrector.
    """

    ds: float = 0.1
    refine: int = 8
    newton: NewtonOptions = field(default_factory=NewtonOptions)
    slide: SlideOptions = field(default_factory=SlideOptions)


@dataclass(frozen=True)
class BristledResult:
    """A batch's run, arrays over its D designs.

    Attributes:
        front: x of the front body node after the gravity step and after each cycle, mm
            (D, cycles + 1).
        work: the actuators' work, mJ. dissipation: the energy dissipated (sliding and
            snaps), mJ. coulomb: its sliding part mu N |dT|, mJ. elastic, gravity: change
            of the bristles' elastic and the body's gravitational energy over the strokes,
            mJ. force_work: sum f ds of the actuators' force over the steps (a check of
            ``work``), mJ.
        lifts: tips lifting off the substrate or touching down again.
        unconverged: equilibrium solves that did not converge.
        stalled: steps whose slide corrector did not settle within its iterations.
        s_max: the designs' strokes, mm.
    """

    front: np.ndarray
    work: np.ndarray
    dissipation: np.ndarray
    coulomb: np.ndarray
    elastic: np.ndarray
    gravity: np.ndarray
    force_work: np.ndarray
    lifts: np.ndarray
    unconverged: np.ndarray
    stalled: np.ndarray
    s_max: np.ndarray

    @property
    def advance_per_cycle(self) -> np.ndarray:
        """The front's advance over each cycle, mm (D, cycles)."""
        return np.diff(self.front, axis=1)

    @property
    def net_advance(self) -> np.ndarray:
        """The front's advance over the strokes, mm (D,)."""
        return self.front[:, -1] - self.front[:, 0]

    @property
    def balance_residual(self) -> np.ndarray:
        """W - (dE_el + dE_g + D), mJ (zero by construction; see :mod:`.crawl`)."""
        return self.work - (self.elastic + self.gravity + self.dissipation)

    @property
    def ok(self) -> np.ndarray:
        """Every equilibrium solve converged and every step's slides settled (D,) bool;
        where not, the design's numbers are not to be used."""
        return (self.unconverged == 0) & (self.stalled == 0) & np.isfinite(self.work)


def _bodies(designs) -> tuple[Bodies, np.ndarray]:
    n_b = max(len(d.bristles) for d in designs)
    D = len(designs)
    empty = Chain(1.0, 2.0, 1.0, 1.0, 1.0, 1.0, -math.pi / 2, 0.1)
    chains = np.empty((D, n_b), dtype=object)
    place = np.zeros((D, n_b))
    on = np.zeros((D, n_b), bool)
    weight = np.zeros((D, n_b))
    behind = np.zeros((D, n_b, n_b - 1))
    for k, d in enumerate(designs):
        m = len(d.bristles)
        for i in range(n_b):
            chains[k, i] = chain_of(d.bristles[i]) if i < m else empty
        place[k, :m] = d.places
        place[k, m:] = d.places[-1]
        on[k, :m] = True
        share = d.body_mass / m
        for i, b in enumerate(d.bristles):
            mean_h = 0.5 * (b.thickness_clamp + b.thickness_tip)
            own = d.bristle_density * b.width * b.length * mean_h
            weight[k, i] = (share + own) * d.gravity
            behind[k, i, :i] = 1.0
        behind[k, m:, : m - 1] = 1.0
    bodies = Bodies(
        chain_fields(chains),
        place,
        behind,
        on,
        np.array([d.link_length for d in designs], float),
        weight,
        np.array([d.free_pitch for d in designs], bool),
    )
    return bodies, np.array([d.s_max for d in designs], float)


def _contacts(designs, bodies: Bodies) -> Contacts:
    for d in designs:
        if len(set(d.bristles)) != 1:
            raise InputError("the bristled model needs one bristle geometry per design")
    keys = [
        (d.surface, d.bristles[0], round(float(bodies.weight[k, 0]), 6))
        for k, d in enumerate(designs)
    ]
    unique = list(dict.fromkeys(keys))
    table = PathTable.of([path_of(*key) for key in unique])
    which = np.array([unique.index(k) for k in keys])
    return Contacts(table, which, np.array([d.mu for d in designs], float))


def _put_down(bodies: Bodies, contacts: Contacts, designs, newton):
    """The body level with each tip on the substrate at its unloaded place (as the FE
    crawler starts), then in equilibrium under its weight with the tips held: (pose, u)."""
    c = bodies.chain
    reach = c["s1"] + c["l1"] + c["l2"]
    start = np.array([d.start for d in designs])
    x = start[:, None] + bodies.place + reach * np.cos(c["theta_r"])
    which = np.broadcast_to(contacts.which[:, None], x.shape)
    u = contacts.paths.arc_at(which, x)
    tips, _, _ = contacts.frame(u)
    load = np.stack([np.zeros_like(bodies.weight), bodies.weight], -1)
    phi = np.moveaxis(chain_angles_under_force(load, c), 0, -1)
    rod = chain_tip(phi[..., 0], phi[..., 1], c)
    tip_x = rod[..., 0] + c["s1"] * np.cos(c["theta_r"])
    tip_y = rod[..., 1] + c["s1"] * np.sin(c["theta_r"])
    body_y = tips[..., 1] + bodies.link[:, None] - tip_y
    body_y = np.where(bodies.on, body_y, np.inf).min(axis=1)
    shift = tip_x - reach * np.cos(c["theta_r"])
    body_x = start - np.where(bodies.on, shift, 0.0).sum(axis=1) / bodies.on.sum(axis=1)
    q = np.stack([body_x, body_y, np.zeros(len(start))], -1)
    lam = -load
    s = np.zeros((len(start), bodies.place.shape[1] - 1))
    held = bodies.on.copy()
    q, phi, lam, _ = equilibrium(bodies, q, phi, lam, tips, s, held, newton)
    return (q, phi, lam, held), u


def run(designs, cycles: int = 2, options: RunOptions = RunOptions()) -> BristledResult:
    """Play ``cycles`` breathing strokes on each of ``designs`` (a sequence of
    :class:`BristledDesign`), all at once: every segment shortens from 0 to s~ and back in
    steps of at most ``options.ds`` mm (of the batch's largest s~)."""
    designs = list(designs)
    top = max(d.s_max for d in designs)
    return play(designs, [breathing_fractions(top, options.ds)] * cycles, options)


def breathing_fractions(s_max: float, ds: float) -> np.ndarray:
    """One breathing stroke's values of s / s~, from 0 up to 1 and back to 0 (the first 0
    left out) in steps of at most ``ds`` mm of a stroke ``s_max`` mm."""
    half = max(1, math.ceil(float(s_max) / ds))
    return np.concatenate([np.arange(1, half + 1), np.arange(half - 1, -1, -1)]) / half


def play(designs, strokes, options: RunOptions = RunOptions()) -> BristledResult:
    """Play ``strokes`` on each of ``designs``, all at once: ``strokes`` one sequence per
    cycle of the values the shortening passes through, as fractions of each design's s~
    (from the rest shape; ``options.ds`` is not used). The
    model is quasi-static: only these values matter, not how fast they are played."""
    designs = list(designs)
    # A design whose solve fails is marked (BristledResult.ok), not a warning to print.
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        return _play(designs, [np.asarray(c, dtype=float) for c in strokes], options)


def _play(designs, strokes, options: RunOptions) -> BristledResult:
    for d in designs:
        d.check()
    bodies, s_max = _bodies(designs)
    contacts = _contacts(designs, bodies)
    pose, u = _put_down(bodies, contacts, designs, options.newton)
    segs = bodies.place.shape[1] - 1
    zero = np.zeros((len(designs), segs))
    tally = Tally.zeros(len(designs))
    pose, u = correct(bodies, contacts, pose, u, zero, tally, options.slide, options.newton)
    e0 = energy(bodies, pose[0], pose[1], zero)
    tally = Tally.zeros(len(designs))
    front = [_front(bodies, pose[0])]
    s_old = zero
    state = (pose, u, None)
    for ramp in strokes:
        for frac in ramp:
            s_new = np.repeat((frac * s_max)[:, None], segs, axis=1)
            state = step(
                bodies,
                contacts,
                state,
                s_old,
                s_new,
                tally,
                options.slide,
                options.newton,
                options.refine,
            )
            s_old = s_new
        front.append(_front(bodies, state[0][0]))
    pose = state[0]
    e1 = energy(bodies, pose[0], pose[1], zero)
    return BristledResult(
        front=np.stack(front, -1),
        work=tally.work,
        dissipation=tally.dissipation,
        coulomb=tally.coulomb,
        elastic=e1[0] - e0[0],
        gravity=e1[1] - e0[1],
        force_work=tally.force_work,
        lifts=tally.lifts,
        unconverged=tally.unconverged,
        stalled=tally.stalled,
        s_max=s_max,
    )


def _front(bodies: Bodies, q) -> np.ndarray:
    last = np.where(bodies.on, bodies.place, -np.inf).max(axis=1)
    return q[:, 0] + last * np.cos(q[:, 2])
