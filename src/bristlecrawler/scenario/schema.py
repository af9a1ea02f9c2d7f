"""The scenario schema: the TOML edge of :class:`bristlecrawler.crawler.CrawlerSpec`.

Every default is read from the spec's dataclasses, so the schema and the Python API cannot
disagree. Units: mm, N, s, t, MPa.
"""

from __future__ import annotations

from typing import Literal

from pydantic import Field, model_validator

from bristlecrawler.crawler.spec import (
    ALPHA_LIMIT_DEG,
    Actuation,
    Body,
    Bristle,
    Contact,
    Damping,
    Solver,
)
from bristlecrawler.errors import InputError
from bristlecrawler.scenario.strict import SafeName, StrictSection, section_of
from bristlecrawler.scenario.substrate import GroovesConfig, SubstrateConfig

_BODY, _BRISTLE, _CONTACT = Body(), Bristle(), Contact()
_DAMPING, _ACTUATION = Damping(), Actuation()


class _Section(StrictSection):
    """A section of a scenario (see :class:`StrictSection`)."""


def _pos(default: float, text: str, le: float, ge: float | None = None):
    """A positive physical quantity with an upper bound (and a lower one where a smaller
    value would break the arithmetic rather than the physics)."""
    if ge is None:
        return Field(default, gt=0, le=le, allow_inf_nan=False, description=text)
    return Field(default, ge=ge, le=le, allow_inf_nan=False, description=text)


#: Largest length anywhere in a scenario, mm (10 m): the FE model's coordinates stay far
#: from round-off trouble, and any real crawler fits.
MAX_LENGTH = 1e4


class BodyConfig(_Section):
    """Rigid body: a bar whose length follows the actuator, with point masses at its ends."""

    length: float = _pos(
        _BODY.length,
        "rest distance between the first and the last bristle (the two ends; the "
        "bristles are spread evenly over it), mm",
        MAX_LENGTH,
    )
    mass: float = _pos(
        _BODY.mass,
        "total mass of the body, shared equally by one point mass above each bristle "
        "(the paper: 55 g, 27.5 g at each end; at most 1 t), t",
        1.0,
    )
    link_length: float = _pos(
        _BODY.link_length,
        "rigid vertical links from each end down to a bristle clamp, mm (not given in "
        "the paper; a studied parameter)",
        MAX_LENGTH,
    )
    free_pitch: bool = Field(_BODY.free_pitch, description="body free to pitch (else kept level)")


class BristleConfig(_Section):
    """Tapered rectangular silicone bristle (Shore A 40), clamped at alpha from the vertical."""

    length: float = _pos(_BRISTLE.length, "bristle length, mm", MAX_LENGTH)
    width: float = _pos(_BRISTLE.width, "out-of-plane width b, mm", MAX_LENGTH)
    thickness_clamp: float = _pos(
        _BRISTLE.thickness_clamp, "thickness at the clamp h0, mm", MAX_LENGTH
    )
    thickness_tip: float = _pos(_BRISTLE.thickness_tip, "thickness at the tip h1, mm", MAX_LENGTH)
    youngs_modulus: float = _pos(
        _BRISTLE.youngs_modulus, "Young's modulus E, MPa (1e-6 to 1e7)", 1e7, ge=1e-6
    )
    poisson_ratio: float = Field(
        _BRISTLE.poisson_ratio, gt=-1.0, lt=0.5, description="Poisson's ratio, -"
    )
    density: float = _pos(
        _BRISTLE.density, "mass density, t/mm^3 (1.3 g/cm^3; 1e-15 to 1e-7)", 1e-7, ge=1e-15
    )
    alpha_deg: float = Field(
        _BRISTLE.alpha_deg,
        gt=-ALPHA_LIMIT_DEG,
        lt=ALPHA_LIMIT_DEG,
        allow_inf_nan=False,
        description="inclination from the vertical, degrees; tips trail (positive: sliding "
        "along the grain is rightward)",
    )
    elements: int = Field(_BRISTLE.elements, ge=2, le=2000, description="beam elements per bristle")
    count: int = Field(
        2,
        ge=2,
        le=50,
        description="number of bristles, spread evenly over the body length (one body "
        "segment, with its own actuator, between neighbours)",
    )
    shear: bool = Field(_BRISTLE.shear, description="shear-deformable (Timoshenko-like) beam")


class DampingConfig(_Section):
    """Rayleigh damping: by default mass-proportional with a ratio at the first resonance."""

    ratio: float = Field(
        _DAMPING.ratio, ge=0.0, lt=1.0, description="damping ratio at the reference frequency, -"
    )
    kind: Literal["mass", "stiffness", "explicit"] = Field(
        _DAMPING.kind,
        description="Rayleigh damping proportional to the mass or to the stiffness, with "
        "the ratio at the first resonance of the settled crawler; or 'explicit' a0, a1",
    )
    a0: float = Field(
        _DAMPING.a0,
        ge=0.0,
        le=1e6,
        allow_inf_nan=False,
        description="explicit mass coefficient, 1/s",
    )
    a1: float = Field(
        _DAMPING.a1,
        ge=0.0,
        le=1e3,
        allow_inf_nan=False,
        description="explicit stiffness coefficient, s",
    )


class ActuationConfig(_Section):
    """Step 2: the prescribed shortening of the body."""

    kind: Literal["sin2", "history", "sma"] = Field(
        "sin2",
        description="stroke: s_max sin^2(pi t / period), a recorded history (history), or "
        "the closed-loop SMA actuator model (sma)",
    )
    s_max: float = _pos(_ACTUATION.s_max, "peak shortening s~ of each body segment, mm", MAX_LENGTH)
    period: float = _pos(_ACTUATION.period, "cycle period T, s (1e-3 to 1e5)", 1e5, ge=1e-3)
    cycles: int = Field(_ACTUATION.cycles, ge=1, le=10_000, description="number of cycles")
    history: str | None = Field(
        None,
        description="CSV file of a shortening history (columns t in s and s in mm), "
        "relative to the scenario file",
    )
    settle_time: float = _pos(_ACTUATION.settle_time, "step 1 (gravity) duration, s", 1e4)
    gait: Literal["breathing", "peristaltic"] = Field(
        _ACTUATION.gait,
        description="breathing: every segment follows s(t) together; peristaltic: segment j "
        "follows s(t - j lag) (with more than two bristles)",
    )
    lag: float = Field(
        _ACTUATION.lag,
        ge=0.0,
        le=1e5,
        allow_inf_nan=False,
        description="delay between neighbouring segments of a peristaltic gait, s",
    )

    @model_validator(mode="after")
    def _history(self) -> ActuationConfig:
        if self.kind == "history" and not self.history:
            raise ValueError("actuation.kind = 'history' needs actuation.history = 'file.csv'")
        if self.kind != "history" and self.history is not None:
            # A file that would be silently ignored: the user meant one of the two.
            raise ValueError(
                f"actuation.history is set but actuation.kind is {self.kind!r}, which does "
                "not read it: set actuation.kind = 'history' too (simulate --history FILE "
                "does both), or leave the history out"
            )
        return self


#: Implicit dynamics with an adaptive step: the table of :class:`crawler.Solver`'s settings.
SolverConfig = section_of(Solver, _Section, "Implicit dynamics with an adaptive step.")


class OutputConfig(_Section):
    """What a run writes."""

    frames_per_cycle: int = Field(
        40, ge=2, le=100_000, description="frames per cycle saved in crawler.nc and the VTK series"
    )
    vtk: bool = Field(True, description="write the ParaView series vtk/crawler.pvd")
    figures: bool = Field(True, description="write delta_vs_s.png, shapes.png and connector.png")
    animation: bool = Field(
        True, description="write crawler.gif (and crawler.mp4 with the `video` extra)"
    )


#: Largest friction coefficient a scenario may give: far above any measured pair.
MAX_MU = 10.0


class ContactConfig(_Section):
    """Contact of the bristles with the substrate."""

    mu: float = Field(
        _CONTACT.mu,
        ge=0.0,
        le=MAX_MU,
        allow_inf_nan=False,
        description="Coulomb friction coefficient bristle/substrate, dimensionless",
    )
    nodes: Literal["tip", "all"] = Field(
        _CONTACT.nodes, description="contact nodes: the bristle tips only, or every bristle node"
    )
    surface: bool = Field(
        _CONTACT.surface,
        description="contact points on both faces of the beam (h/2 from the axis, turning "
        "with the section) rather than on its axis",
    )
    discs: bool = Field(
        _CONTACT.discs,
        description="with surface = false: each axis contact point is a disc of radius h/2 "
        "(the local half thickness), so the faces rather than the axis touch flat parts of "
        "the substrate; friction acts on the node's translation (no moment)",
    )
    corners: bool = Field(
        _CONTACT.corners,
        description="corner-to-face contact: the substrate's convex corners (land edges), "
        "where it has any (a flat substrate has none), against both faces of every bristle "
        "element, so a sharp corner cannot pass between contact points",
    )
    penalty_load: float | None = Field(
        _CONTACT.penalty_load,
        gt=0.0,
        le=1e6,
        allow_inf_nan=False,
        description="penalty load, N: the normal penalty keeps penetration below 1e-3 mm and "
        "the stick drift below contact.stick_drift at this load; null: the weight on one "
        "bristle",
    )
    stick_drift: float = Field(
        _CONTACT.stick_drift,
        gt=0.0,
        le=1.0,
        allow_inf_nan=False,
        description="elastic tangential displacement in stick at the friction limit of the "
        "penalty load, mm (sets the stick penalty k_t = mu load / stick_drift). `paper` "
        "sets 1e-3 mm: the same gait as 1e-4 mm in 40 % fewer Newton iterations. "
        "`paper-vertical` keeps 1e-4 mm: with 1e-3, at the end of its 0.5 s gravity step "
        "each tip stands on one face point and the settled state is unstable (a negative "
        "lowest eigenvalue of the tangent)",
    )
    active_points: int | None = Field(
        _CONTACT.active_points,
        ge=1,
        le=100_000,
        description="broad phase: contact points evaluated per Newton iteration, the ones "
        "reaching lowest (the corner term is separate). Exact while at most this many "
        "points reach below the substrate's top (the paper run has up to 7); a run where "
        "more do stops with an error naming this parameter. null: every point",
    )
    penetration_limit: float = Field(
        _CONTACT.penetration_limit,
        gt=0.0,
        allow_inf_nan=True,
        description="deepest contact penetration of a converged time step, mm: a deeper one "
        "is rejected and cut, since a land corner that reaches the middle of the 0.5 mm "
        "tip is pushed out through the wrong face (25 times the design penetration; inf: "
        "no limit)",
    )


class Scenario(_Section):
    """A complete finite-element crawler scenario."""

    name: SafeName = Field(
        "custom",
        description="name of the scenario, used in the run folder's name: letters, digits, "
        "'_', '.' and '-', at most 64",
    )
    description: str = Field("", description="one line on what the scenario is")
    body: BodyConfig = BodyConfig()
    bristle: BristleConfig = BristleConfig()
    substrate: SubstrateConfig = GroovesConfig(kind="grooves", width=1.0, depth=0.25, pitch=2.0)
    contact: ContactConfig = ContactConfig()
    damping: DampingConfig = DampingConfig()
    actuation: ActuationConfig = ActuationConfig()
    gravity: float = Field(
        9810.0,
        ge=0.0,
        le=1e6,
        allow_inf_nan=False,
        description="gravitational acceleration, mm/s^2 (0 only with contact.penalty_load)",
    )
    solver: SolverConfig = SolverConfig()
    output: OutputConfig = OutputConfig()

    @model_validator(mode="after")
    def _consistent(self) -> Scenario:
        if self.actuation.kind != "history" and self.actuation.s_max >= self.body.length:
            raise ValueError(
                f"actuation.s_max ({self.actuation.s_max:g} mm) must be smaller than the body "
                f"length ({self.body.length:g} mm)"
            )
        if self.actuation.kind != "history":
            check_bristles_clear(self, self.actuation.s_max)
        check_substrate_scale(self.substrate.model_dump())
        if self.gravity == 0 and self.contact.penalty_load is None:
            raise ValueError(
                "gravity = 0 leaves no weight to press the bristles on the substrate and to "
                "size the contact penalty: give gravity > 0 or contact.penalty_load (N)"
            )
        if self.actuation.kind != "history":
            check_step_count(self, self.actuation.cycles * self.actuation.period)
        if self.bristle.thickness_tip > self.bristle.thickness_clamp:
            # The bristle tapers from its clamp: a thicker tip is a typo, not a design.
            raise ValueError(
                f"bristle.thickness_tip ({self.bristle.thickness_tip:g} mm) must not exceed "
                f"bristle.thickness_clamp ({self.bristle.thickness_clamp:g} mm): the bristle "
                "tapers from its clamp"
            )
        return self


#: Most time steps a scenario may ask for (at least cycles * period / dt_max): the paper
#: run takes about 2,400.
MAX_STEPS = 1e6


def check_step_count(sc: Scenario, duration: float) -> None:
    """ValueError if a stroke of ``duration`` s needs more than MAX_STEPS time steps of
    solver.dt_max."""
    steps = duration / sc.solver.dt_max
    if steps > MAX_STEPS:
        raise ValueError(
            f"the stroke ({duration:.3g} s) takes at least {steps:.3g} time steps of "
            f"solver.dt_max = {sc.solver.dt_max:g} s, more than {MAX_STEPS:g}: shorten the "
            "run (actuation.cycles, actuation.period, the history) or raise solver.dt_max"
        )


def check_bristles_clear(sc: Scenario, s_max: float) -> None:
    """ValueError if neighbouring bristles overlap at the peak shortening ``s_max`` (mm) of
    a segment (the spec's rule, :meth:`CrawlerSpec.check_clearance`)."""
    from bristlecrawler.crawler.spec import CrawlerSpec, uniform_bristles

    b = sc.bristle
    template = Bristle(
        length=b.length,
        alpha_deg=b.alpha_deg,
        thickness_clamp=b.thickness_clamp,
        thickness_tip=b.thickness_tip,
    )
    spec = CrawlerSpec(bristles=uniform_bristles(b.count, sc.body.length, template))
    try:
        spec.check_clearance(s_max)
    except InputError as exc:
        raise ValueError(str(exc).removeprefix("actuation: ")) from None


def check_substrate_scale(sub: dict) -> None:
    """Bounds a ``[substrate]`` table's own schema does not state: lengths within
    +-MAX_LENGTH mm (a phase of 1e308 mm divides to nonsense). Numbers only; other values
    are left to the table's schema."""

    def numbers(value):
        if isinstance(value, bool):
            return []
        if isinstance(value, float | int):
            return [value]
        if isinstance(value, list | tuple):
            return [x for v in value for x in numbers(v)]
        return []

    for key, value in sub.items():
        if key in ("kind", "rise_fraction"):
            continue
        if any(abs(v) > MAX_LENGTH for v in numbers(value)):
            raise ValueError(f"substrate.{key} must be within +-{MAX_LENGTH:g} mm, got {value}")
