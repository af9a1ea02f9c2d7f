"""What a drag test of one bristle gives the reduced model, as a typed result.

The drag test itself (:mod:`bristlecrawler.crawler.drag`) is FE; its summary lives in the
results layer, below both the FE crawler that writes it and the reduced crawler that
reads it (:meth:`ReducedCrawler.from_drag`), so that both share one type. ``to_dict``
gives the keys of the drag test's ``summary.json``.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from bristlecrawler.errors import InputError
from bristlecrawler.results.keys import (
    ENERGY_BALANCE_REL_ERROR,
    K_N_PER_MM,
    NEWTON_ITERATIONS,
    SETTLE_CREEP_MM,
    SETTLE_SPEED_MM_S,
    STEPS,
    WALL_TIME_S,
)
from bristlecrawler.results.texture import TextureLaw


def _number(value: Any) -> float:
    """A JSON number as a float; null (how the files write NaN) and a missing value NaN."""
    return math.nan if value is None else float(value)


@dataclass(frozen=True)
class Sliding:
    """Sliding in one direction: the mean force (N, magnitude), its pitch-to-pitch
    standard deviation and range (N), the peak magnitude (N), and the pitches it was
    read over."""

    mean: float
    scatter: float
    low: float
    high: float
    peak: float
    pitches: int

    def to_dict(self, name: str) -> dict[str, Any]:
        """The values under ``name`` (``fp`` or ``fn``) with units in the keys."""
        return {
            f"{name}_N": self.mean,
            f"{name}_scatter_N": self.scatter,
            f"{name}_range_N": [self.low, self.high],
            f"{name}_peak_N": self.peak,
            f"{name}_pitches": self.pitches,
        }

    @staticmethod
    def none_dict(name: str) -> dict[str, float]:
        """The keys a direction that never slid writes (NaN)."""
        nan = math.nan
        return {f"{name}_N": nan, f"{name}_scatter_N": nan, f"{name}_peak_N": nan}

    @classmethod
    def from_dict(cls, data: dict[str, Any], name: str) -> Sliding | None:
        """The sliding ``name`` of a summary mapping; None where its mean is missing or
        NaN (the test did not slide that way)."""
        mean = _number(data.get(f"{name}_N"))
        if math.isnan(mean):
            return None
        low, high = data.get(f"{name}_range_N") or (None, None)
        return cls(
            mean,
            _number(data.get(f"{name}_scatter_N")),
            _number(low),
            _number(high),
            _number(data.get(f"{name}_peak_N")),
            int(data.get(f"{name}_pitches", 0)),
        )


@dataclass(frozen=True)
class DragSummary:
    """The parameters a drag test gives (NaN where the test does not give one).

    Attributes:
        k: secant stiffness of the first loading, N/mm: the reduced model's k.
        k_unload: mean secant stiffness after the reversals, N/mm.
        k_initial: tangent stiffness while the tip first sticks, N/mm.
        along, against: sliding along the grain (F_p) and against it (F_n), N; None
            where the test did not slide that way over a whole pitch.
        mu_load: friction coefficient times the load, N.
        load: vertical load on the bristle, N.
        dissipation_per_mm: friction and damping dissipation per mm of travel, mJ/mm.
        energy_balance_rel_error: energy-balance residual relative to the work.
        steps, newton_iterations: counters of the solve.
        wall_time: wall time of the solve, s.
        texture: the bristle's texture law, or None where the test did not slide both ways.
        settle_speed: the carriage's speed at the end of the gravity step, mm/s.
        settle_creep: how far it would still move there under that step's damping, mm.
    """

    k: float
    k_unload: float
    k_initial: float
    along: Sliding | None
    against: Sliding | None
    mu_load: float
    load: float
    dissipation_per_mm: float
    energy_balance_rel_error: float
    steps: int
    newton_iterations: int
    wall_time: float
    texture: TextureLaw | None = None
    settle_speed: float = math.nan
    settle_creep: float = math.nan

    @property
    def fp(self) -> float:
        """Mean resistance along the grain F_p, N (NaN without it)."""
        return self.along.mean if self.along else math.nan

    @property
    def fn(self) -> float:
        """Mean resistance against the grain F_n, N (NaN without it)."""
        return self.against.mean if self.against else math.nan

    @property
    def fp_over_k(self) -> float:
        """F_p / k, mm (NaN without either)."""
        k = self.k
        return self.fp / k if k and math.isfinite(k) else math.nan

    def to_dict(self) -> dict[str, Any]:
        """The drag test's ``summary.json`` values, units in the keys."""

        def part(s: Sliding | None, name: str) -> dict[str, Any]:
            return Sliding.none_dict(name) if s is None else s.to_dict(name)

        return {
            K_N_PER_MM: self.k,
            "k_unload_N_per_mm": self.k_unload,
            "k_initial_N_per_mm": self.k_initial,
            **part(self.along, "fp"),
            **part(self.against, "fn"),
            "fp_over_k_mm": self.fp_over_k,
            "mu_load_N": self.mu_load,
            "load_N": self.load,
            "dissipation_mJ_per_mm": self.dissipation_per_mm,
            ENERGY_BALANCE_REL_ERROR: self.energy_balance_rel_error,
            STEPS: self.steps,
            NEWTON_ITERATIONS: self.newton_iterations,
            WALL_TIME_S: self.wall_time,
            "texture": self.texture.to_dict() if self.texture is not None else None,
            SETTLE_SPEED_MM_S: self.settle_speed,
            SETTLE_CREEP_MM: self.settle_creep,
        }

    @classmethod
    def from_dict(cls, data: dict[str, Any]) -> DragSummary:
        """The summary back from :meth:`to_dict`'s mapping (a ``summary.json`` or a cache
        entry); a value it lacks, or null, is NaN (counters 0, texture None)."""
        law = data.get("texture")
        return cls(
            k=_number(data.get(K_N_PER_MM)),
            k_unload=_number(data.get("k_unload_N_per_mm")),
            k_initial=_number(data.get("k_initial_N_per_mm")),
            along=Sliding.from_dict(data, "fp"),
            against=Sliding.from_dict(data, "fn"),
            mu_load=_number(data.get("mu_load_N")),
            load=_number(data.get("load_N")),
            dissipation_per_mm=_number(data.get("dissipation_mJ_per_mm")),
            energy_balance_rel_error=_number(data.get(ENERGY_BALANCE_REL_ERROR)),
            steps=int(data.get(STEPS, 0)),
            newton_iterations=int(data.get(NEWTON_ITERATIONS, 0)),
            wall_time=_number(data.get(WALL_TIME_S)),
            texture=TextureLaw.from_dict(law) if isinstance(law, dict) else law,
            settle_speed=_number(data.get(SETTLE_SPEED_MM_S)),
            settle_creep=_number(data.get(SETTLE_CREEP_MM)),
        )


def summary_of(drag) -> DragSummary:
    """What a reduced crawler reads of a drag test, typed: the :class:`DragSummary` given,
    or read from a drag test's result (its ``summarize()``, or the mapping its
    ``summary()`` gives) or from a summary mapping (a ``summary.json``)."""
    if isinstance(drag, DragSummary):
        return drag
    if hasattr(drag, "summarize"):
        return drag.summarize()
    if hasattr(drag, "summary"):
        drag = drag.summary()
    if isinstance(drag, DragSummary):
        return drag
    if not isinstance(drag, Mapping):
        raise InputError(f"not a drag test's summary: {type(drag).__name__}")
    return DragSummary.from_dict(drag)
