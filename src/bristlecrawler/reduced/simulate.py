"""One-call runs of the reduced model: stroke or gait in, :class:`ReducedResult` out."""

from __future__ import annotations

import numpy as np

from bristlecrawler.errors import InputError
from bristlecrawler.reduced.gaits import Gait, breathing
from bristlecrawler.reduced.model import ReducedModel
from bristlecrawler.reduced.solver import ReducedResult
from bristlecrawler.reduced.strokes import SampledStroke, Stroke


def _excursion_bounds(s: np.ndarray) -> np.ndarray:
    """Sample indices where strokes start and end: a stroke rises above half of the range
    and ends at the first local minimum within 2 % of the range of the initial level."""
    base = s[0]
    span = float(s.max() - base)
    if span <= 0:
        return np.array([0, s.size - 1])
    bounds, away, j = [0], False, 1
    while j < s.size:
        if not away and s[j] > base + 0.5 * span:
            away = True
        elif away and s[j] <= base + 0.02 * span:
            while j + 1 < s.size and s[j + 1] <= s[j]:
                j += 1
            bounds.append(j)
            away = False
        j += 1
    if bounds[-1] != s.size - 1:
        bounds.append(s.size - 1)
    return np.asarray(bounds, dtype=int)


def cycle_bounds(gait: Gait, t: np.ndarray, cycles: int) -> np.ndarray:
    """Sample indices at which cycles start (and the last sample)."""
    period = getattr(gait.stroke, "period", None)
    if period is None:
        return _excursion_bounds(gait.shortenings(t, cycles)[:, 0])
    marks = np.arange(int(np.floor(t[-1] / period + 1e-9)) + 1) * period
    idx = np.unique(np.searchsorted(t, marks - 1e-9 * period))
    idx = idx[idx < t.size]
    if idx[-1] != t.size - 1:
        idx = np.append(idx, t.size - 1)
    return idx


def simulate(
    crawler: ReducedModel,
    stroke: Stroke | Gait,
    cycles: int = 5,
    samples_per_cycle: int = 2000,
) -> ReducedResult:
    """Run the exact quasi-static solver over ``cycles`` strokes.

    Args:
        crawler: a reduced model (:class:`ReducedModel`: the paper's law, a texture, ...).
        stroke: a stroke (all segments breathe in phase) or a :class:`Gait`.
        cycles: number of cycles (ignored for a sampled history, which is replayed whole).
        samples_per_cycle: samples per period for analytic strokes (rounded up to even so
            that turning points are samples); a sampled history uses its own samples.
    """
    if not isinstance(crawler, ReducedModel):
        raise InputError(f"not a reduced model: {type(crawler).__name__}")
    if int(cycles) != cycles or cycles < 1:
        raise InputError(f"cycles must be an integer >= 1, got {cycles}")
    if int(samples_per_cycle) != samples_per_cycle or samples_per_cycle < 2:
        raise InputError(f"samples per cycle must be an integer >= 2, got {samples_per_cycle}")
    gait = stroke if isinstance(stroke, Gait) else breathing(stroke, crawler.n_bristles - 1)
    if gait.n_segments != crawler.n_bristles - 1:
        raise InputError(
            f"gait drives {gait.n_segments} segments but the crawler has {crawler.n_bristles - 1}"
        )
    crawler.check_stroke(gait.stroke.s_max)
    t = gait.sample_times(int(cycles), int(samples_per_cycle))
    shortening = gait.shortenings(t, int(cycles))
    if isinstance(gait.stroke, SampledStroke):
        t = t + gait.stroke.t[0]
    bounds = cycle_bounds(gait, t - t[0], int(cycles))
    return crawler.solve(t, shortening, bounds)
