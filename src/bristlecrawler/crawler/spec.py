"""The design of an FE bristle crawler as plain frozen dataclasses (no pydantic).

A :class:`CrawlerSpec` holds the body, a sequence of bristles, the substrate, the contact
definition, the damping, the actuation and the solver options (the parts are declared in
:mod:`.parts` and :mod:`.solver`). Build one directly (:meth:`CrawlerSpec.paper`,
:func:`dataclasses.replace`), or load a TOML scenario with
:func:`bristlecrawler.scenario.load_spec`. Every default is the one the scenario schema
shows: the schema reads its defaults from these classes.

Units: mm, N, s, tonne (so MPa, t/mm^3, mJ).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from bristlecrawler.contact.substrates import Grooves, Substrate
from bristlecrawler.crawler.parts import (
    MAX_STEPS,
    Actuation,
    Body,
    Bristle,
    Contact,
    Damping,
)
from bristlecrawler.crawler.solver import Solver
from bristlecrawler.errors import InputError
from bristlecrawler.fe.options import check_settings, setting


def _paper_substrate():
    # The paper's grooves (Section 2: 1 mm wide, 0.25 mm deep); the pitch is not given.
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
    gravity: float = setting(
        9810.0,
        "gravitational acceleration, mm/s^2 (0 only with contact.penalty_load)",
        ge=0.0,
        le=1e6,
    )
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
        """Raise :class:`InputError` (one line) for a design that cannot be built or a
        stroke it cannot make: :meth:`check_design`, then :meth:`check_stroke`. Every
        rule on a design lives here or in its parts' ``check``; the scenario schema runs
        these same checks."""
        self.check_design()
        self.check_stroke()

    def check_design(self) -> None:
        """InputError for a design that cannot be built, whatever its stroke: a setting
        out of its range, bristles out of place, no weight, a bristle that cannot carry
        its share of it."""
        self.body.check()
        if len(self.bristles) < 2:
            raise InputError(f"a crawler needs at least 2 bristles, got {len(self.bristles)}")
        for i, b in enumerate(self.bristles):
            b.check(f"bristles[{i}].")
        for part in (self.contact, self.damping, self.actuation, self.solver):
            part.check()
        check_settings(self)
        self.rules()

    def rules(self) -> None:
        """InputError for parts that do not fit together: bristles out of place, no
        weight and no penalty load, a bristle that cannot carry its share of the weight
        (each part's own settings checked already)."""
        if not isinstance(self.substrate, Substrate):
            raise InputError(
                "substrate must be a bristlecrawler.contact.substrates.Substrate (Flat, "
                f"Grooves, Sawtooth, Polyline, or your own), got {type(self.substrate).__name__}"
            )
        self._check_positions()
        if self.gravity == 0 and self.contact.penalty_load is None:
            raise InputError(
                "gravity = 0 leaves no weight to press the bristles on the substrate and to "
                "size the contact penalty: give gravity > 0 or contact.penalty_load (N)"
            )
        from bristlecrawler.crawler.support import check_support

        check_support(self)

    def check_stroke(self) -> None:
        """InputError for a stroke the design cannot make: a peak shortening of the body
        length or more, bristles brought into each other (:meth:`check_clearance`), or
        more than :data:`MAX_STEPS` time steps of ``solver.dt_max``."""
        peak, length = self.actuation.peak, self.body.length
        if peak >= length:
            what = "actuation.s_max" if self.actuation.history is None else "history: shortening"
            raise InputError(
                f"{what} ({peak:g} mm) must be smaller than the body length ({length:g} mm)"
            )
        self.check_clearance(peak)
        duration = self.actuation.stroke_duration(self.segments)
        steps = duration / self.solver.dt_max
        if steps > MAX_STEPS:
            raise InputError(
                f"the stroke ({duration:.3g} s) takes at least {steps:.3g} time steps of "
                f"solver.dt_max = {self.solver.dt_max:g} s, more than {MAX_STEPS:g}: shorten "
                "the run (actuation.cycles, actuation.period, the history) or raise "
                "solver.dt_max"
            )

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
                    f"a peak shortening of {peak:g} mm (actuation.s_max or the "
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
