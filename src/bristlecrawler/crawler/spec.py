"""The design of an FE bristle crawler as plain frozen dataclasses (no pydantic).

A :class:`CrawlerSpec` holds the body, a sequence of bristles, the substrate, the contact
definition, the damping, the actuation and the solver options. Build one directly
(:meth:`CrawlerSpec.paper`, :func:`dataclasses.replace`), or load a TOML scenario with
:func:`bristlecrawler.scenario.load_spec`. Every default below is the one the scenario
schema shows: the schema reads its defaults from these classes.

Units: mm, N, s, tonne (so MPa, t/mm^3, mJ).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any, Literal

import numpy as np

from bristlecrawler.crawler.solver import Solver
from bristlecrawler.errors import InputError
from bristlecrawler.fe.options import renamed

#: Largest inclination from the vertical a bristle may have, degrees.
ALPHA_LIMIT_DEG = 80.0


def _positive(name: str, value: float) -> None:
    if not (isinstance(value, int | float) and math.isfinite(value) and value > 0):
        raise InputError(f"{name} must be a positive finite number, got {value!r}")


@dataclass(frozen=True)
class Body:
    """The rigid body: a bar through the bristles' clamps whose segments the actuator shortens.

    Attributes:
        length: rest distance between the first and the last bristle's body nodes, mm; with
            :meth:`CrawlerSpec.with_bristles` the bristles are spread evenly over it.
        mass: total mass of the body, t, shared equally by the body nodes (one above each
            bristle); the paper's 55 g is 27.5 g at each end.
        link_length: length of the rigid vertical links from the body nodes down to the
            bristle clamps, mm (not given in the paper).
        free_pitch: the body may pitch (rotate in its plane); False keeps it level.
    """

    length: float = 100.0
    mass: float = 5.5e-5
    link_length: float = 10.0
    free_pitch: bool = True

    def check(self) -> None:
        _positive("body.length", self.length)
        _positive("body.mass", self.mass)
        _positive("body.link_length", self.link_length)


@dataclass(frozen=True)
class Bristle:
    """A tapered rectangular silicone bristle clamped to the body (paper Section 3).

    Attributes:
        position: place of its clamp along the body from the first body node, mm.
        alpha_deg: inclination from the vertical, degrees, in (-80, 80); the tip trails
            (alpha > 0: sliding along the grain is rightward).
        length: bristle length, mm.
        width: out-of-plane width b, mm.
        thickness_clamp: thickness h0 at the clamp, mm.
        thickness_tip: thickness h1 at the tip, mm (linear taper from h0).
        youngs_modulus: E, MPa (Shore A 40 silicone: 1.1).
        poisson_ratio: nu, -.
        density: rho, t/mm^3 (1.3 g/cm^3 = 1.3e-9).
        elements: beam elements along the bristle.
        shear: shear-deformable (Timoshenko-like) elements.
    """

    position: float = 0.0
    alpha_deg: float = 45.0
    length: float = 5.0
    width: float = 30.0
    thickness_clamp: float = 3.0
    thickness_tip: float = 0.5
    youngs_modulus: float = 1.1
    poisson_ratio: float = 0.45
    density: float = 1.3e-9
    elements: int = 20
    shear: bool = True

    @property
    def alpha(self) -> float:
        """Inclination, rad."""
        return math.radians(self.alpha_deg)

    def section(self):
        """The bristle's :class:`fe.TaperedRect` (linear taper from clamp to tip)."""
        from bristlecrawler.fe import TaperedRect

        return TaperedRect(
            E=self.youngs_modulus,
            b=self.width,
            h0=self.thickness_clamp,
            h1=self.thickness_tip,
            rho=self.density,
            nu=self.poisson_ratio,
            shear=self.shear,
        )

    def thickness(self, fraction) -> np.ndarray:
        """Section thickness (mm) at ``fraction`` (0 at the clamp, 1 at the tip) of the length."""
        return self.section().thickness(fraction)

    def node_thickness(self) -> np.ndarray:
        """Thickness (mm) at the ``elements + 1`` nodes, clamp to tip."""
        return self.thickness(np.arange(self.elements + 1) / self.elements)

    def normal(self) -> np.ndarray:
        """Unit normal of the undeformed bristle's axis (the '+' face), (2,)."""
        return np.array([math.cos(self.alpha), -math.sin(self.alpha)])

    @property
    def mass(self) -> float:
        """Mass, t."""
        mean_h = 0.5 * (self.thickness_clamp + self.thickness_tip)
        return self.density * self.width * self.length * mean_h

    def check(self, where: str) -> None:
        for name in ("length", "width", "thickness_clamp", "thickness_tip"):
            _positive(f"{where}.{name}", getattr(self, name))
        for name in ("youngs_modulus", "density"):
            _positive(f"{where}.{name}", getattr(self, name))
        if not -1.0 < self.poisson_ratio < 0.5:
            raise InputError(
                f"{where}.poisson_ratio must be in (-1, 0.5), got {self.poisson_ratio}"
            )
        a = self.alpha_deg
        if not (math.isfinite(a) and -ALPHA_LIMIT_DEG < a < ALPHA_LIMIT_DEG):
            raise InputError(
                f"{where}.alpha_deg must be in (-{ALPHA_LIMIT_DEG:g}, {ALPHA_LIMIT_DEG:g}) "
                f"degrees, got {a}"
            )
        if not (isinstance(self.elements, int) and 2 <= self.elements <= 2000):
            raise InputError(f"{where}.elements must be a whole number in [2, 2000]")
        if not math.isfinite(self.position):
            raise InputError(f"{where}.position must be finite, got {self.position}")


@renamed(max_penetration="penetration_limit")
@dataclass(frozen=True)
class Contact:
    """Contact of the bristles with the rigid substrate (penalty Coulomb friction).

    Attributes:
        mu: Coulomb friction coefficient bristle/substrate, -.
        nodes: "tip" (the tips only) or "all" (every bristle node).
        surface: contact points on both faces of the beam (h/2 from the axis, turning with
            the section) rather than on its axis.
        discs: with ``surface`` off, each axis point is a disc of radius h/2.
        corners: the substrate's convex corners against both faces of every element,
            where it has any (a plane has none, and gets no corner term).
        penalty_load: load (N) at which penetration stays below 1e-3 mm and the stick drift
            below ``stick_drift``; None: the weight on one bristle.
        stick_drift: elastic tangential displacement in stick at the friction limit of the
            penalty load, mm.
        active_points: broad phase, contact points evaluated per Newton iteration (the
            ones reaching lowest); None: every point.
        penetration_limit: a step that converges deeper than this (mm) is cut (the
            penalty's own design penetration is 1e-3 mm at ``penalty_load``);
            ``max_penetration`` before, still taken with a DeprecationWarning.
    """

    mu: float = 0.65
    nodes: Literal["tip", "all"] = "all"
    surface: bool = True
    discs: bool = False
    corners: bool = True
    penalty_load: float | None = None
    stick_drift: float = 1e-4
    active_points: int | None = 16
    penetration_limit: float = 0.025

    def check(self) -> None:
        if not (math.isfinite(self.mu) and self.mu >= 0):
            raise InputError(f"contact.mu must be a finite number >= 0, got {self.mu}")
        if self.nodes not in ("tip", "all"):
            raise InputError(f"contact.nodes must be 'tip' or 'all', got {self.nodes!r}")
        _positive("contact.stick_drift", self.stick_drift)
        if self.penalty_load is not None:
            _positive("contact.penalty_load", self.penalty_load)
        if not self.penetration_limit > 0:
            raise InputError(
                f"contact.penetration_limit must be > 0 mm, got {self.penetration_limit}"
            )
        if self.active_points is not None and self.active_points < 1:
            raise InputError(f"contact.active_points must be >= 1, got {self.active_points}")


@dataclass(frozen=True)
class Damping:
    """Rayleigh damping C = a0 M + a1 K.

    Attributes:
        kind: "mass" or "stiffness" (the ratio is met at the first resonance after the
            gravity step, by modal analysis), or "explicit" (a0, a1 as given).
        ratio: damping ratio at that frequency, -.
        a0: explicit mass coefficient, 1/s.
        a1: explicit stiffness coefficient, s.
    """

    kind: Literal["mass", "stiffness", "explicit"] = "mass"
    ratio: float = 0.15
    a0: float = 0.0
    a1: float = 0.0

    @property
    def stiffness_proportional(self) -> bool:
        """Whether the programs need the a1 K v product."""
        return self.kind == "stiffness" or (self.kind == "explicit" and self.a1 != 0.0)

    def check(self) -> None:
        if self.kind not in ("mass", "stiffness", "explicit"):
            raise InputError(f"damping.kind must be mass, stiffness or explicit, got {self.kind!r}")
        if not 0.0 <= self.ratio < 1.0:
            raise InputError(f"damping.ratio must be in [0, 1), got {self.ratio}")
        for name in ("a0", "a1"):
            v = getattr(self, name)
            if not (math.isfinite(v) and v >= 0):
                raise InputError(f"damping.{name} must be a finite number >= 0, got {v}")


@dataclass(frozen=True)
class Actuation:
    """The prescribed shortening of every body segment after the gravity step.

    Attributes:
        s_max: peak shortening s~ of each segment, mm (sin^2 stroke).
        period: cycle period T, s.
        cycles: number of strokes.
        settle_time: duration of the gravity step before the stroke, s.
        history: a sampled shortening (times s, shortenings mm, from t = 0) used instead of
            the sin^2 stroke; None: ``s(t) = s_max sin^2(pi t / T)``.
        gait: "breathing" (every segment follows s(t) together) or "peristaltic" (segment j
            follows s(t - j lag)); as in the reduced model.
        lag: delay between neighbouring segments of a peristaltic gait, s (>= 0).
    """

    s_max: float = 20.0
    period: float = 20.0
    cycles: int = 5
    settle_time: float = 0.5
    history: tuple[tuple[float, ...], tuple[float, ...]] | None = None
    gait: Literal["breathing", "peristaltic"] = "breathing"
    lag: float = 0.0

    @property
    def peak(self) -> float:
        """Largest shortening of a segment, mm."""
        return max(self.history[1]) if self.history is not None else self.s_max

    def delays(self, segments: int) -> tuple[float, ...]:
        """Start of each segment's stroke after the gravity step, s."""
        if self.gait == "breathing":
            return (0.0,) * segments
        return tuple(j * self.lag for j in range(segments))

    def stroke_duration(self, segments: int) -> float:
        """Duration of the stroke of all segments, s."""
        one = self.history[0][-1] if self.history is not None else self.cycles * self.period
        return float(one) + max(self.delays(segments))

    def check(self) -> None:
        if self.history is None:
            _positive("actuation.s_max", self.s_max)
            _positive("actuation.period", self.period)
        else:
            t, s = (np.asarray(a, dtype=float) for a in self.history)
            if t.size < 2 or t.shape != s.shape or not np.all(np.diff(t) > 0):
                raise InputError("actuation.history needs >= 2 samples with increasing times")
            if not (np.all(np.isfinite(s)) and t[0] == 0.0):
                raise InputError("actuation.history must start at t = 0 with finite values")
        if not (isinstance(self.cycles, int) and self.cycles >= 1):
            raise InputError(f"actuation.cycles must be a whole number >= 1, got {self.cycles!r}")
        _positive("actuation.settle_time", self.settle_time)
        if self.gait not in ("breathing", "peristaltic"):
            raise InputError(f"actuation.gait must be breathing or peristaltic, got {self.gait!r}")
        if not (math.isfinite(self.lag) and self.lag >= 0):
            raise InputError(f"actuation.lag must be a finite number >= 0 s, got {self.lag}")


def _paper_substrate():
    # The paper's grooves (Section 2: 1 mm wide, 0.25 mm deep); the pitch is not given.
    from bristlecrawler.contact.substrates import Grooves

    return Grooves(width=1.0, depth=0.25, pitch=2.0, fillet_top=0.02)


@dataclass(frozen=True)
class CrawlerSpec:
    """A complete FE crawler design.

    Attributes:
        body: :class:`Body`.
        bristles: the bristles, ordered by position (at least two; each with its
            own clamp position, inclination, section and material).
        substrate: a rigid substrate of :mod:`bristlecrawler.contact.substrates`
            (``Grooves``, ``Flat``, ``Sawtooth``, ``Polyline``).
        contact, damping, actuation, solver: see their classes.
        gravity: gravitational acceleration, mm/s^2.
        name: a label for outputs.
    """

    body: Body = field(default_factory=Body)
    bristles: tuple[Bristle, ...] = (Bristle(position=0.0), Bristle(position=100.0))
    substrate: Any = field(default_factory=_paper_substrate)
    contact: Contact = field(default_factory=Contact)
    damping: Damping = field(default_factory=Damping)
    actuation: Actuation = field(default_factory=Actuation)
    solver: Solver = field(default_factory=Solver)
    gravity: float = 9810.0
    name: str = "custom"

    @classmethod
    def paper(cls, **changes) -> CrawlerSpec:
        """The paper's crawler (Section 3, alpha = pi/4) as the `paper` scenario runs it:
        grooves of pitch 2 mm with 0.02 mm fillets, stick drift 1e-3 mm and no bound on the
        energy a step may lose (see the scenario file)."""
        spec = cls(
            contact=Contact(stick_drift=1e-3),
            solver=Solver(energy_loss_tol=math.inf),
            name="paper",
        )
        return dataclasses.replace(spec, **changes)

    @property
    def segments(self) -> int:
        """Number of actuated body segments (bristles - 1)."""
        return len(self.bristles) - 1

    def with_bristles(self, count: int, **bristle_changes) -> CrawlerSpec:
        """The spec with ``count`` bristles spread evenly over the body, each the first
        bristle with ``bristle_changes`` applied (e.g. ``alpha_deg=30``)."""
        if not (isinstance(count, int) and count >= 2):
            raise InputError(f"a crawler needs at least 2 bristles, got {count!r}")
        template = dataclasses.replace(self.bristles[0], **bristle_changes)
        xs = np.linspace(0.0, self.body.length, count)
        return dataclasses.replace(
            self,
            bristles=tuple(dataclasses.replace(template, position=float(x)) for x in xs),
        )

    def replace_bristles(self, **changes) -> CrawlerSpec:
        """The spec with ``changes`` applied to every bristle."""
        return dataclasses.replace(
            self, bristles=tuple(dataclasses.replace(b, **changes) for b in self.bristles)
        )

    def check(self) -> None:
        """Raise :class:`InputError` (one line) for a design that cannot be built."""
        self.body.check()
        if len(self.bristles) < 2:
            raise InputError(f"a crawler needs at least 2 bristles, got {len(self.bristles)}")
        for i, b in enumerate(self.bristles):
            b.check(f"bristles[{i}]")
        self._check_positions()
        for part in (self.contact, self.damping, self.actuation, self.solver):
            part.check()
        if not (math.isfinite(self.gravity) and self.gravity >= 0):
            raise InputError(f"gravity must be a finite number >= 0 mm/s^2, got {self.gravity}")
        self._check_stroke()
        from bristlecrawler.crawler.support import check_support

        check_support(self)

    def _check_positions(self) -> None:
        xs = [b.position for b in self.bristles]
        L = self.body.length
        for i, x in enumerate(xs):
            if not -1e-9 * L <= x <= L * (1 + 1e-9):
                raise InputError(
                    f"bristles[{i}].position = {x:g} mm is outside the body [0, {L:g}] mm"
                )
        for i in range(1, len(xs)):
            if not xs[i] > xs[i - 1]:
                raise InputError(
                    f"bristles[{i}].position = {xs[i]:g} mm must be beyond bristles[{i - 1}] "
                    f"({xs[i - 1]:g} mm): two bristles at one place, or out of order"
                )

    def _check_stroke(self) -> None:
        self.check_clearance(self.actuation.peak)

    def check_clearance(self, peak: float) -> None:
        """InputError if a shortening of ``peak`` (mm) of a segment brings its two bristles
        into each other: their clamps sit the segment apart, each reaches length *
        sin(alpha) along the body from its clamp (the tips trail), and the clamps are
        thickness_clamp thick. The one rule for the spec and the scenario file."""
        for i in range(self.segments):
            a, b = self.bristles[i], self.bristles[i + 1]
            gap = b.position - a.position
            # The closest approach of the two bristles' footprints along the body, with
            # the sections' half thickness at the clamps.
            ext_a = (
                min(0.0, -a.length * math.sin(a.alpha)),
                max(0.0, -a.length * math.sin(a.alpha)),
            )
            ext_b = (
                min(0.0, -b.length * math.sin(b.alpha)),
                max(0.0, -b.length * math.sin(b.alpha)),
            )
            room = gap + ext_b[0] - ext_a[1] - 0.5 * (a.thickness_clamp + b.thickness_clamp)
            if not peak < room:
                raise InputError(
                    f"actuation: a peak shortening of {peak:g} mm (actuation.s_max or the "
                    f"history) brings bristles {i} and {i + 1} into each other: their "
                    f"clamps come {gap - peak:g} mm apart, and they overlap unless that "
                    f"exceeds their reach along the body and clamps, {gap - room:.3g} mm "
                    "(bristle length * sin(alpha) + thickness_clamp)"
                )

    def positions(self) -> np.ndarray:
        """Clamp positions along the body, mm."""
        return np.array([b.position for b in self.bristles])


def uniform_bristles(
    count: int, length: float, template: Bristle | None = None
) -> tuple[Bristle, ...]:
    """``count`` copies of ``template`` spread evenly over a body of ``length`` mm."""
    t = template or Bristle()
    return tuple(dataclasses.replace(t, position=float(x)) for x in np.linspace(0.0, length, count))


__all__: Sequence[str] = (
    "Actuation",
    "Body",
    "Bristle",
    "Contact",
    "CrawlerSpec",
    "Damping",
    "Solver",
    "uniform_bristles",
)
