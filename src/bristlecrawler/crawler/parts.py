"""The parts of an FE bristle crawler's design (:class:`~.spec.CrawlerSpec`): body,
bristle, contact, damping and actuation, each a frozen dataclass whose settings are
declared once (name, default, meaning with its unit, range); the scenario schema reads
its tables from these declarations.

Units: mm, N, s, tonne (so MPa, t/mm^3, mJ).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Literal, TypeAlias

import numpy as np

from bristlecrawler.contact.coulomb import FrictionLaw
from bristlecrawler.contact.power_law import EXPONENT_RANGE, HERTZ_EXPONENT
from bristlecrawler.errors import InputError
from bristlecrawler.fe import TaperedRect
from bristlecrawler.settings import MAX_LENGTH, Settings, renamed, setting

#: Largest inclination from the vertical a bristle may have, degrees.
ALPHA_LIMIT_DEG = 80.0


#: Largest friction coefficient a design may give: far above any measured pair.
MAX_MU = 10.0
#: The friction laws a scenario can name (``contact.friction``): the registered ones.
FrictionName: TypeAlias = Literal[tuple(FrictionLaw.laws)]  # type: ignore[valid-type]

#: Most time steps a stroke may ask for (at least its duration / solver.dt_max): the
#: paper run takes about 2,400.
MAX_STEPS = 1e6


def _length(default: float, doc: str, **kw) -> Any:
    """A positive length up to :data:`MAX_LENGTH` (``doc`` ends in ``, mm``)."""
    return setting(default, doc, gt=0.0, le=MAX_LENGTH, **kw)


@dataclass(frozen=True)
class Body(Settings):
    """The rigid body: a bar through the bristles' clamps whose segments the actuator
    shortens. Each attribute is a declared setting: its meaning, unit and range are the
    ``[body]`` table's (``bristlecrawler scenario keys``)."""

    length: float = _length(
        100.0,
        "rest distance between the first and the last bristle (the two ends; the "
        "bristles are spread evenly over it), mm",
    )
    mass: float = setting(
        5.5e-5,
        "total mass of the body, shared equally by one point mass above each bristle "
        "(the paper: 55 g, 27.5 g at each end; at most 1 t), t",
        gt=0.0,
        le=1.0,
    )
    link_length: float = _length(
        10.0,
        "rigid vertical links from each end down to a bristle clamp, mm (not given in "
        "the paper; a studied parameter)",
    )
    free_pitch: bool = setting(True, "body free to pitch (else kept level)")

    def check(self, prefix: str = "body.") -> None:
        super().check(prefix)


@dataclass(frozen=True)
class Bristle(Settings):
    """A tapered rectangular silicone bristle (Shore A 40) clamped to the body at
    ``alpha_deg`` from the vertical (paper Section 3); linear taper from h0 at the clamp
    to h1 at the tip. Each attribute but ``position`` is a declared setting of the
    ``[bristle]`` table (``bristlecrawler scenario keys``)."""

    #: Place of its clamp along the body from the first body node, mm (a scenario
    #: spreads ``count`` bristles evenly over the body instead).
    position: float = 0.0
    alpha_deg: float = setting(
        45.0,
        "inclination from the vertical, degrees; tips trail (positive: sliding "
        "along the grain is rightward)",
        gt=-ALPHA_LIMIT_DEG,
        lt=ALPHA_LIMIT_DEG,
    )
    length: float = _length(5.0, "bristle length, mm")
    width: float = _length(30.0, "out-of-plane width b, mm")
    thickness_clamp: float = _length(3.0, "thickness at the clamp h0, mm")
    thickness_tip: float = _length(0.5, "thickness at the tip h1, mm")
    youngs_modulus: float = setting(1.1, "Young's modulus E, MPa (1e-6 to 1e7)", ge=1e-6, le=1e7)
    poisson_ratio: float = setting(0.45, "Poisson's ratio, -", gt=-1.0, lt=0.5)
    density: float = setting(
        1.3e-9, "mass density, t/mm^3 (1.3 g/cm^3; 1e-15 to 1e-7)", ge=1e-15, le=1e-7
    )
    elements: int = setting(20, "beam elements per bristle", ge=2, le=2000, structural=True)
    shear: bool = setting(True, "shear-deformable (Timoshenko-like) beam", structural=True)

    @property
    def alpha(self) -> float:
        """Inclination, rad."""
        return math.radians(self.alpha_deg)

    def section(self):
        """The bristle's :class:`fe.TaperedRect` (linear taper from clamp to tip)."""
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

    def check(self, prefix: str = "bristle.") -> None:
        super().check(prefix)

    def rules(self, prefix: str = "bristle.") -> None:
        """InputError for a clamp out of place or a tip thicker than the clamp."""
        if not math.isfinite(self.position):
            raise InputError(f"{prefix}position must be finite, got {self.position}")
        if self.thickness_tip > self.thickness_clamp:
            # The bristle tapers from its clamp: a thicker tip is a typo, not a design.
            raise InputError(
                f"{prefix}thickness_tip ({self.thickness_tip:g} mm) must not exceed "
                f"{prefix}thickness_clamp ({self.thickness_clamp:g} mm): the bristle "
                "tapers from its clamp"
            )


@renamed(max_penetration="penetration_limit")
@dataclass(frozen=True)
class Contact(Settings):
    """Contact of the bristles with the rigid substrate (penalty Coulomb friction). Each
    attribute is a declared setting of the ``[contact]`` table (``bristlecrawler scenario
    keys``); ``max_penetration``, the name of ``penetration_limit`` before, is still taken
    with a DeprecationWarning."""

    mu: float = setting(
        0.65,
        "friction coefficient bristle/substrate (with the power law: at the penalty "
        "load), dimensionless",
        ge=0.0,
        le=MAX_MU,
    )
    # The alias is a Literal of words, as immutable as the other settings' defaults.
    friction: FrictionName = setting(  # noqa: RUF009
        "coulomb",
        "friction law: coulomb (F = mu p_N) or power (F = mu L (p_N / L)^m, L the "
        "penalty load; rubber-like contact)",
        structural=True,
    )
    friction_exponent: float | None = setting(
        None,
        "the power law's exponent m, dimensionless; null: 2/3 (a Hertzian contact). "
        "Only with friction = power",
        ge=EXPONENT_RANGE[0],
        le=EXPONENT_RANGE[1],
        none=True,
    )
    friction_load: float | None = setting(
        None,
        "the power law's reference load L, where its friction is mu L, N; null: the "
        "weight on one bristle. Only with friction = power",
        gt=0.0,
        le=1e6,
        none=True,
    )
    nodes: Literal["tip", "all"] = setting(
        "all",
        "contact nodes: the bristle tips only, or every bristle node",
        structural=True,
    )
    surface: bool = setting(
        True,
        "contact points on both faces of the beam (h/2 from the axis, turning "
        "with the section) rather than on its axis",
        structural=True,
    )
    discs: bool = setting(
        False,
        "with surface = false: each axis contact point is a disc of radius h/2 "
        "(the local half thickness), so the faces rather than the axis touch flat parts of "
        "the substrate; friction acts on the node's translation (no moment)",
        structural=True,
    )
    corners: bool = setting(
        True,
        "corner-to-face contact: the substrate's convex corners (land edges), "
        "where it has any (a flat substrate has none), against both faces of every bristle "
        "element, so a sharp corner cannot pass between contact points",
        structural=True,
    )
    penalty_load: float | None = setting(
        None,
        "penalty load, N: the normal penalty keeps penetration below 1e-3 mm and "
        "the stick drift below contact.stick_drift at this load; null: the weight on one "
        "bristle",
        gt=0.0,
        le=1e6,
        none=True,
    )
    stick_drift: float = setting(
        1e-4,
        "elastic tangential displacement in stick at the friction limit of the "
        "penalty load, mm (sets the stick penalty k_t = mu load / stick_drift). `paper` "
        "sets 1e-3 mm: the same gait as 1e-4 mm in 40 % fewer Newton iterations. "
        "`paper-vertical` keeps 1e-4 mm: with 1e-3, at the end of its 0.5 s gravity step "
        "each tip stands on one face point and the settled state is unstable (a negative "
        "lowest eigenvalue of the tangent)",
        gt=0.0,
        le=1.0,
    )
    active_points: int | None = setting(
        16,
        "broad phase: contact points evaluated per Newton iteration, the ones "
        "reaching lowest (the corner term is separate). Exact while at most this many "
        "points reach below the substrate's top (the paper run has up to 7); a run where "
        "more do stops with an error naming this parameter. null: every point",
        ge=1,
        le=100_000,
        none=True,
        structural=True,
    )
    penetration_limit: float = setting(
        0.025,
        "deepest contact penetration of a converged time step, mm: a deeper one "
        "is rejected and cut, since a land corner that reaches the middle of the 0.5 mm "
        "tip is pushed out through the wrong face (25 times the design penetration; inf: "
        "no limit)",
        gt=0.0,
        inf=True,
        structural=True,
    )

    def check(self, prefix: str = "contact.") -> None:
        super().check(prefix)

    def rules(self, prefix: str = "contact.") -> None:
        for key in ("friction_exponent", "friction_load"):
            if getattr(self, key) is not None and self.friction != "power":
                raise InputError(
                    f"{prefix}{key} is the power law's: set {prefix}friction = "
                    f'"power" or leave it out (the {self.friction} law has none)'
                )

    def law_options(self, weight: float) -> dict[str, float]:
        """The keywords of the friction law's ``for_reference_load`` beyond mu, load and
        stick drift (``weight``: the weight on one bristle, N, the power law's default
        reference load)."""
        if self.friction == "power":
            m = HERTZ_EXPONENT if self.friction_exponent is None else self.friction_exponent
            return {"exponent": m, "reference": self.friction_load or weight}
        return {}


@dataclass(frozen=True)
class Damping(Settings):
    """Rayleigh damping C = a0 M + a1 K: by default mass-proportional with a ratio at the
    first resonance. Each attribute is a declared setting of the ``[damping]`` table."""

    kind: Literal["mass", "stiffness", "explicit"] = setting(
        "mass",
        "Rayleigh damping proportional to the mass or to the stiffness, with "
        "the ratio at the first resonance of the settled crawler; or 'explicit' a0, a1",
        structural=True,
    )
    ratio: float = setting(0.15, "damping ratio at the reference frequency, -", ge=0.0, lt=1.0)
    a0: float = setting(0.0, "explicit mass coefficient, 1/s", ge=0.0, le=1e6)
    a1: float = setting(0.0, "explicit stiffness coefficient, s", ge=0.0, le=1e3)

    @property
    def stiffness_proportional(self) -> bool:
        """Whether the programs need the a1 K v product."""
        return self.kind == "stiffness" or (self.kind == "explicit" and self.a1 != 0.0)

    def check(self, prefix: str = "damping.") -> None:
        super().check(prefix)


@dataclass(frozen=True)
class Actuation(Settings):
    """The prescribed shortening of every body segment after the gravity step (step 2).
    Each attribute but ``history`` is a declared setting of the ``[actuation]`` table.

    ``history``: a sampled shortening (times s, shortenings mm, from t = 0) used instead
    of the sin^2 stroke ``s(t) = s_max sin^2(pi t / T)``; None: the sin^2 stroke (a
    scenario names a CSV file instead, ``actuation.history``).
    """

    s_max: float = _length(20.0, "peak shortening s~ of each body segment, mm")
    period: float = setting(20.0, "cycle period T, s (1e-3 to 1e5)", ge=1e-3, le=1e5)
    cycles: int = setting(5, "number of cycles", ge=1, le=10_000)
    settle_time: float = setting(0.5, "step 1 (gravity) duration, s", gt=0.0, le=1e4)
    history: tuple[tuple[float, ...], tuple[float, ...]] | None = None
    gait: Literal["breathing", "peristaltic"] = setting(
        "breathing",
        "breathing: every segment follows s(t) together; peristaltic: segment j "
        "follows s(t - j lag) (with more than two bristles)",
    )
    lag: float = setting(
        0.0,
        "delay between neighbouring segments of a peristaltic gait, s",
        ge=0.0,
        le=1e5,
    )

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

    def check(self, prefix: str = "actuation.") -> None:
        super().check(prefix)

    def rules(self, prefix: str = "actuation.") -> None:
        """InputError for a history that is not a stroke from t = 0."""
        if self.history is not None:
            t, s = (np.asarray(a, dtype=float) for a in self.history)
            if t.size < 2 or t.shape != s.shape or not np.all(np.diff(t) > 0):
                raise InputError(f"{prefix}history needs >= 2 samples with increasing times")
            if not (np.all(np.isfinite(s)) and t[0] == 0.0):
                raise InputError(f"{prefix}history must start at t = 0 with finite values")
