"""Gaits: how the N-1 actuated segments of an N-bristle body follow a stroke.

* breathing: every segment follows the same shortening s(t) at the same time (the paper's
  reciprocal, breathing-like deformation; for two bristles the only possible gait).
* peristaltic: segment j follows ``s(t - d_j)`` with ``d_j = j * lag`` (a travelling wave of
  contraction; ``lag > 0`` runs from the rear, bristle 0, to the front, ``lag < 0`` the other
  way). Each segment rests (s = its initial value) before its delay and completes the same
  number of strokes, so the run is ``max(d_j)`` longer than the stroke.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from bristlecrawler.errors import InputError
from bristlecrawler.reduced.strokes import Stroke


@dataclass(frozen=True)
class Gait:
    """A stroke and one delay per segment (s, all >= 0, the smallest equal to 0)."""

    stroke: Stroke
    delays: tuple[float, ...]
    name: str = "breathing"

    def __post_init__(self) -> None:
        d = np.asarray(self.delays, dtype=float)
        if d.size < 1 or not np.all(np.isfinite(d)) or np.any(d < 0):
            raise InputError(f"gait delays must be finite and >= 0, got {self.delays}")

    @property
    def n_segments(self) -> int:
        return len(self.delays)

    def duration(self, cycles: int) -> float:
        return self.stroke.duration(cycles) + max(self.delays)

    def sample_times(self, cycles: int, samples_per_cycle: int) -> np.ndarray:
        base = self.stroke.sample_times(cycles, samples_per_cycle)
        if max(self.delays) == 0.0:
            return base
        times = np.unique(np.concatenate([base + d for d in self.delays] + [base]))
        return times[times <= self.duration(cycles) + 1e-12 * max(1.0, times[-1])]

    def shortenings(self, t: np.ndarray, cycles: int) -> np.ndarray:
        """Segment shortenings (mm), shape (len(t), n_segments)."""
        t = np.asarray(t, dtype=float)
        end = self.stroke.duration(cycles)
        out = np.empty((t.size, self.n_segments))
        for j, d in enumerate(self.delays):
            local = np.clip(t - d, 0.0, end)
            out[:, j] = self.stroke(local)
        return out


def breathing(stroke: Stroke, n_segments: int = 1) -> Gait:
    """All segments follow ``stroke`` in phase."""
    return Gait(stroke, (0.0,) * int(n_segments), "breathing")


def peristaltic(stroke: Stroke, n_segments: int, lag: float) -> Gait:
    """Segment j follows ``stroke`` delayed by ``j * lag`` seconds (shifted so delays >= 0)."""
    if not np.isfinite(lag):
        raise InputError(f"peristaltic lag must be finite, got {lag}")
    d = np.arange(int(n_segments)) * float(lag)
    d -= d.min()
    return Gait(stroke, tuple(float(x) for x in d), "peristaltic")
