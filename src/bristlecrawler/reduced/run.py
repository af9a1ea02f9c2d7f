"""A run of the reduced model as one options object: every setting of ``bristlecrawler
reduced`` (and of a reduced design study's base) declared once, with its default (the
paper's, Section 4), its meaning and unit, and its range; the rules between them in
:meth:`ReducedRun.rules`. The command's options and a study's table are generated from
these declarations (:mod:`bristlecrawler.scenario.reduced`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import numpy as np

from bristlecrawler.errors import InputError
from bristlecrawler.reduced.crawler import (
    DEFAULT_FN_OVER_FP,
    PAPER_CYCLES,
    PAPER_FP,
    PAPER_K,
    PAPER_LENGTH,
    PAPER_PERIOD,
    PAPER_S_MAX,
    ReducedCrawler,
)
from bristlecrawler.reduced.gaits import Gait, breathing, peristaltic
from bristlecrawler.reduced.strokes import Sin2Stroke, Stroke, TriangleStroke
from bristlecrawler.settings import MAX_LENGTH, Settings, setting

#: Bounds of the physical parameters: forces in N, F_p/k in mm (lengths: MAX_LENGTH).
MIN_FORCE = 1e-9
MAX_FORCE = 1e6
MIN_FP_OVER_K = 1e-9
#: Most samples of a run (cycles x samples per cycle): about a gigabyte of results.
MAX_SAMPLES = 1e8


@dataclass(frozen=True)
class ReducedRun(Settings):
    """Parameters of a reduced-model run. Defaults reproduce the paper (Section 4)."""

    s_max: float = setting(
        PAPER_S_MAX, "peak shortening s~ of each segment, mm", gt=0, le=MAX_LENGTH
    )
    fp: float = setting(PAPER_FP, "F_p, resistance along the grain, N", ge=MIN_FORCE, le=MAX_FORCE)
    fn: float | None = setting(
        None,
        f"F_n, resistance against the grain, N; None: {DEFAULT_FN_OVER_FP:g} F_p",
        ge=MIN_FORCE,
        le=MAX_FORCE,
        none=True,
    )
    k: float = setting(PAPER_K, "bristle stiffness, N/mm", ge=1e-9, le=1e9)
    length: float = setting(
        PAPER_LENGTH, "distance between first and last bristle, mm", ge=1e-3, le=MAX_LENGTH
    )
    cycles: int = setting(PAPER_CYCLES, "number of strokes", ge=1, le=100_000)
    period: float = setting(PAPER_PERIOD, "stroke period T, s", ge=1e-6, le=1e7)
    bristles: int = setting(2, "number of bristles N", ge=2, le=10_000)
    gait: Literal["breathing", "peristaltic"] = setting(
        "breathing",
        "gait of the segments; breathing: all at once, peristaltic: one after the other",
    )
    lag: float | None = setting(
        None,
        "peristaltic delay between neighbouring segments, s; None: period / 4",
        ge=-1e7,
        le=1e7,
        none=True,
    )
    stroke: Literal["sin2", "triangle"] = setting(
        "sin2",
        "shape of the analytic stroke; sin2: s_max sin^2(pi t / period), triangle: a "
        "triangle wave of the same period",
    )
    actuator: Literal["sin2", "sma"] = setting(
        "sin2",
        "prescribed stroke, or the closed-loop SMA actuator model with target s_max (then "
        "period is not used)",
    )
    history: str | None = setting(
        None, "CSV file with columns t (s) and s (mm); None: the analytic stroke", none=True
    )
    texture: str | None = setting(
        None,
        "a drag test's summary.json: the crawler on its texture law (k, F_p(x), F_n(x) "
        "over a pitch); fp, fn and k are then not used",
        none=True,
    )
    samples_per_cycle: int = setting(
        2000, "samples per period of an analytic stroke", ge=2, le=10_000_000
    )

    def rules(self, prefix: str = "") -> None:
        """InputError naming the settings that contradict each other."""
        c = self.fp / self.k
        if not MIN_FP_OVER_K <= c <= MAX_LENGTH:
            raise InputError(
                f"fp / k ({c:g} mm, the bristle's deflection at sliding) must be within "
                f"[{MIN_FP_OVER_K:g}, {MAX_LENGTH:g}] mm"
            )
        if self.cycles * self.samples_per_cycle > MAX_SAMPLES:
            raise InputError(
                f"cycles x samples_per_cycle ({self.cycles * self.samples_per_cycle:g}) must "
                f"be at most {MAX_SAMPLES:g} samples"
            )
        if self.history is not None and self.actuator == "sma":
            raise InputError("give either a history file or actuator = 'sma', not both")
        fn = np.nan if self.fn is None else self.fn
        found = first_inconsistency(
            self.fp, fn, self.s_max, self.length, self.bristles, self.history is not None
        )
        if found is not None:
            raise InputError(found[1])

    @property
    def fn_resolved(self) -> float:
        """F_n, N: the given one, or its default share of F_p."""
        return self.fn if self.fn is not None else DEFAULT_FN_OVER_FP * self.fp

    @property
    def lag_resolved(self) -> float:
        """The peristaltic lag, s: the given one, or a quarter period."""
        return self.lag if self.lag is not None else self.period / 4

    def crawler(self) -> ReducedCrawler:
        """The crawler of the paper's friction law these settings describe."""
        return ReducedCrawler.uniform(self.bristles, self.length, self.k, self.fp, self.fn_resolved)

    def analytic_stroke(self) -> Stroke:
        """The analytic stroke these settings describe (sin^2 or triangle)."""
        cls = Sin2Stroke if self.stroke == "sin2" else TriangleStroke
        return cls(self.s_max, self.period)

    def gait_of(self, stroke: Stroke) -> Gait:
        """The gait of ``stroke`` these settings describe."""
        nseg = self.bristles - 1
        if self.gait == "peristaltic":
            return peristaltic(stroke, nseg, self.lag_resolved)
        return breathing(stroke, nseg)


def first_inconsistency(fp, fn, s_max, length, bristles, history: bool = False):
    """The first of a batch of configurations whose values contradict each other, as
    ``(index, message)`` (index into the broadcast, flattened arrays), or None.

    Vectorised so that a design study checks millions of designs at once; fn = NaN stands
    for the default F_n. ``history``: the stroke comes from a file (no bound on s_max here).
    """
    fp, fn, s_max, length, bristles = (
        a.ravel()
        for a in np.broadcast_arrays(
            *(np.asarray(v, float) for v in (fp, fn, s_max, length, bristles))
        )
    )
    fn = np.where(np.isnan(fn), DEFAULT_FN_OVER_FP * fp, fn)
    bad = fn < fp
    if bad.any():
        i = int(np.argmax(bad))
        return i, f"fn ({fn[i]:g} N) must be >= fp ({fp[i]:g} N)"
    if history:
        return None
    seg = length / (bristles - 1)
    bad = s_max >= seg
    if bad.any():
        i = int(np.argmax(bad))
        what = "length L" if bristles[i] == 2 else f"segment length L/(N-1) = {seg[i]:g} mm"
        return i, f"s_max ({s_max[i]:g} mm) must be smaller than the {what}"
    return None
