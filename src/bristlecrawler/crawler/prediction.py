"""The reduced model of a design, fed with drag-test parameters, against the FE crawler.

:func:`reduced_twin` turns a design and a drag test of its bristle into the reduced
crawler (the bristles at the design's places, each with the drag test's k, F_p, F_n);
:func:`reduced_run` plays the design's actuation on it with the exact solver;
:func:`compare` runs the FE crawler too and returns both, side by side, as a
:class:`Prediction`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from bristlecrawler.crawler.metrics import run_metrics
from bristlecrawler.crawler.spec import CrawlerSpec
from bristlecrawler.reduced import (
    ReducedCrawler,
    SampledStroke,
    Sin2Stroke,
    breathing,
    peristaltic,
    simulate,
)
from bristlecrawler.results.metrics import RunMetrics


def reduced_twin(spec: CrawlerSpec, drag) -> ReducedCrawler:
    """The reduced crawler of ``spec``: its bristles at their places along the body, each
    with ``drag``'s k, F_p and F_n (a :class:`~bristlecrawler.results.drag.
    DragSummary`, a drag result, a summary mapping, or one of them per bristle)."""
    x = np.array([b.position for b in spec.bristles])
    return ReducedCrawler.from_drag(drag, len(x), segment_lengths=np.diff(np.sort(x)))


def reduced_gait(spec: CrawlerSpec):
    """The design's actuation as the reduced model's gait (same stroke, gait and lag)."""
    a = spec.actuation
    if a.history is not None:
        stroke = SampledStroke(np.asarray(a.history[0]), np.asarray(a.history[1]))
    else:
        stroke = Sin2Stroke(a.s_max, a.period)
    segments = len(spec.bristles) - 1
    if a.gait == "peristaltic":
        return peristaltic(stroke, segments, a.lag)
    return breathing(stroke, segments)


def reduced_run(spec: CrawlerSpec, drag, samples_per_cycle: int = 2000):
    """The reduced model's :class:`~bristlecrawler.reduced.ReducedResult` for the design's
    actuation, its bristles from ``drag``."""
    return simulate(
        reduced_twin(spec, drag),
        reduced_gait(spec),
        cycles=spec.actuation.cycles,
        samples_per_cycle=samples_per_cycle,
    )


@dataclass(frozen=True)
class Prediction:
    """FE and reduced model on one design.

    Attributes:
        s_max: peak shortening, mm. alpha_deg: the first bristle's inclination, degrees.
        fe_advance, reduced_advance: net advance of the front end, mm.
        fe_work, reduced_work: actuator work, mJ.
        fe_per_cycle, reduced_per_cycle: advance of each cycle, mm.
        pitch: the substrate's groove pitch, mm (the FE crawler's quantum of advance).
        fp_over_k: the drag test's F_p / k, mm.
    """

    s_max: float
    alpha_deg: float
    fe_advance: float
    reduced_advance: float
    fe_work: float
    reduced_work: float
    fe_per_cycle: np.ndarray
    reduced_per_cycle: np.ndarray
    pitch: float
    fp_over_k: float

    @property
    def advance_error(self) -> float:
        """Reduced minus FE net advance, mm."""
        return self.reduced_advance - self.fe_advance

    @property
    def work_error(self) -> float:
        """Reduced over FE work, minus 1 (NaN without FE work)."""
        return self.reduced_work / self.fe_work - 1.0 if self.fe_work else math.nan

    def row(self) -> dict:
        """The values of one row of the prediction table (units in the keys)."""
        return {
            "alpha_deg": self.alpha_deg,
            "s_max_mm": self.s_max,
            "fe_advance_mm": self.fe_advance,
            "reduced_advance_mm": self.reduced_advance,
            "advance_error_mm": self.advance_error,
            "fe_work_mJ": self.fe_work,
            "reduced_work_mJ": self.reduced_work,
            "work_error_rel": self.work_error,
            "pitch_mm": self.pitch,
            "fp_over_k_mm": self.fp_over_k,
            "four_fp_over_k_mm": 4.0 * self.fp_over_k,
        }


def compare(spec: CrawlerSpec, drag, fe_history) -> Prediction:
    """The reduced model (its bristles from ``drag``) beside the FE crawler's history of
    the same design (``crawler.run(spec)``)."""

    red = RunMetrics.from_reduced(reduced_run(spec, drag))
    fe = run_metrics(fe_history)
    twin = reduced_twin(spec, drag)
    return Prediction(
        s_max=spec.actuation.peak,
        alpha_deg=math.degrees(spec.bristles[0].alpha),
        fe_advance=fe.net_advance,
        reduced_advance=red.net_advance,
        fe_work=fe.work,
        reduced_work=red.work,
        fe_per_cycle=np.asarray(fe.advance_per_cycle),
        reduced_per_cycle=np.asarray(red.advance_per_cycle),
        pitch=spec.substrate.period,
        fp_over_k=float(twin.fp[0] / twin.k[0]),
    )
