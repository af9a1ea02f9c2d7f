"""The scenario schema: the TOML edge of :class:`bristlecrawler.crawler.CrawlerSpec`.

Every table is generated from the settings the spec's dataclasses declare (name, default,
meaning with its unit, range: :func:`bristlecrawler.fe.options.setting`), and every rule
between settings is the spec's own ``check``, so the schema and the Python API cannot
disagree. Units: mm, N, s, t, MPa.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Literal

from pydantic import Field, model_validator

from bristlecrawler.crawler.parts import (
    MAX_LENGTH,
    MAX_MU,
    MAX_STEPS,
    Actuation,
    Body,
    Bristle,
    Contact,
    Damping,
)
from bristlecrawler.crawler.spec import (
    CrawlerSpec,
    Solver,
    uniform_bristles,
)
from bristlecrawler.errors import InputError
from bristlecrawler.fe.options import Settings, setting
from bristlecrawler.scenario.strict import (
    SafeName,
    StrictSection,
    pydantic_field,
    section_of,
)
from bristlecrawler.scenario.substrate import SUBSTRATE_KINDS, SubstrateConfig

__all__ = [
    "MAX_LENGTH",
    "MAX_MU",
    "MAX_STEPS",
    "ActuationConfig",
    "BodyConfig",
    "BristleConfig",
    "ContactConfig",
    "DampingConfig",
    "Output",
    "OutputConfig",
    "Scenario",
    "SolverConfig",
]


class _Section(StrictSection):
    """A section of a scenario (see :class:`StrictSection`)."""


BodyConfig = section_of(
    Body,
    _Section,
    "Rigid body: a bar whose length follows the actuator, with point masses at its ends.",
)

#: Bristles in a scenario: spread evenly over the body (a Python spec places each).
_COUNT = setting(
    2,
    "number of bristles, spread evenly over the body length (one body segment, with its "
    "own actuator, between neighbours)",
    ge=2,
    le=50,
    structural=True,
)

BristleConfig = section_of(
    Bristle,
    _Section,
    "Tapered rectangular silicone bristle (Shore A 40), clamped at alpha from the vertical.",
    exclude=("position",),
    extra={"count": (int, _COUNT)},
    prefix="bristle.",
)

DampingConfig = section_of(
    Damping,
    _Section,
    "Rayleigh damping: by default mass-proportional with a ratio at the first resonance.",
)

#: How a scenario gives the stroke (a Python spec holds the sampled history itself).
_STROKE_KIND = setting(
    "sin2",
    "stroke: s_max sin^2(pi t / period), a recorded history (history), or "
    "the closed-loop SMA actuator model (sma)",
    structural=True,
)
_HISTORY_FILE = setting(
    None,
    "CSV file of a shortening history (columns t in s and s in mm), relative to the scenario file",
    none=True,
)


def _actuation_rules(table) -> None:
    Actuation(**table.model_dump(exclude={"kind", "history"})).rules(prefix="")
    if table.kind == "history" and not table.history:
        raise InputError("actuation.kind = 'history' needs actuation.history = 'file.csv'")
    if table.kind != "history" and table.history is not None:
        # A file that would be silently ignored: the user meant one of the two.
        raise InputError(
            f"actuation.history is set but actuation.kind is {table.kind!r}, which does "
            "not read it: set actuation.kind = 'history' too (simulate --history FILE "
            "does both), or leave the history out"
        )


ActuationConfig = section_of(
    Actuation,
    _Section,
    "Step 2: the prescribed shortening of the body.",
    exclude=("history",),
    extra={
        "kind": (Literal["sin2", "history", "sma"], _STROKE_KIND),
        "history": (str | None, _HISTORY_FILE),
    },
    rules=_actuation_rules,
)

#: Implicit dynamics with an adaptive step: the table of :class:`crawler.Solver`'s settings.
SolverConfig = section_of(Solver, _Section, "Implicit dynamics with an adaptive step.")


@dataclass(frozen=True)
class Output(Settings):
    """What a run writes."""

    frames_per_cycle: int = setting(
        40, "frames per cycle saved in crawler.nc and the VTK series", ge=2, le=100_000
    )
    vtk: bool = setting(True, "write the ParaView series vtk/crawler.pvd")
    figures: bool = setting(True, "write delta_vs_s.png, shapes.png and connector.png")
    animation: bool = setting(True, "write crawler.gif (and crawler.mp4 with the `video` extra)")


OutputConfig = section_of(Output, _Section, "What a run writes.")

ContactConfig = section_of(Contact, _Section, "Contact of the bristles with the substrate.")

_GRAVITY = next(f for f in dataclasses.fields(CrawlerSpec) if f.name == "gravity")


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
    substrate: SubstrateConfig = SUBSTRATE_KINDS["grooves"](
        kind="grooves", width=1.0, depth=0.25, pitch=2.0
    )
    contact: ContactConfig = ContactConfig()
    damping: DampingConfig = DampingConfig()
    actuation: ActuationConfig = ActuationConfig()
    gravity: float = pydantic_field(_GRAVITY, float)
    solver: SolverConfig = SolverConfig()
    output: OutputConfig = OutputConfig()

    @model_validator(mode="after")
    def _consistent(self) -> Scenario:
        # The rules between tables are the spec's (each table checked its own): check
        # the design these tables describe (with a history, its stroke is checked once
        # the file is read).
        spec = self.design()
        try:
            spec.rules()
            if self.actuation.kind != "history":
                spec.check_stroke()
        except InputError as exc:
            raise ValueError(str(exc)) from None
        return self

    def design(self) -> CrawlerSpec:
        """The :class:`CrawlerSpec` these tables describe, but a history's samples (the
        sin^2 stroke of ``actuation.s_max`` instead; :func:`~bristlecrawler.scenario.to_spec`
        reads the history)."""
        br, a = self.bristle, self.actuation
        template = Bristle(**br.model_dump(exclude={"count"}))
        return CrawlerSpec(
            body=Body(**self.body.model_dump()),
            bristles=uniform_bristles(br.count, self.body.length, template),
            substrate=self.substrate.build(),
            contact=Contact(**self.contact.model_dump()),
            damping=Damping(**self.damping.model_dump()),
            actuation=Actuation(**a.model_dump(exclude={"kind", "history"})),
            solver=Solver(**self.solver.model_dump()),
            gravity=self.gravity,
            name=self.name,
        )
