"""From raw transducer channels to the paper's s(t) and Delta(t), robust to lab artefacts.

* **Dropouts** (NaN samples, empty cells): gaps up to ``max_gap_s`` are bridged by linear
  interpolation; NaN at the ends is trimmed; a longer gap is refused with its time.
* **Segmentation**: strokes are found on s with hysteresis thresholds at 40 % and 60 % of the
  stroke amplitude; a cycle runs from a rest minimum through a peak to the next rest
  minimum. A partial first or last cycle is discarded.
* **Offsets and slow drift of s**: the crawler returns to its rest length at every cycle end
  (the closed-loop control stops there), so s is referenced to a baseline through the rest
  levels at the cycle bounds (piecewise linear in time). This removes the offsets of both
  transducers and the drift of their difference.
* **Delta** is referenced to its value at the start of the first complete cycle. Drift of
  the front transducer alone cannot be told apart from motion and is not removed; it biases
  the per-cycle advance but not the loop shape that :mod:`.fit` uses for F_p/k.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from bristlecrawler.errors import InputError
from bristlecrawler.experiment.recording import Recording


@dataclass(frozen=True)
class GaitSignals:
    """Cleaned signals and the cycles found in them.

    Attributes:
        t: time, s. s: shortening, mm. delta: front-end advance, mm.
        cycles: integer array (n_cycles, 3): sample indices of start, peak, end.
        filled: True where a sample was interpolated across a dropout.
        notes: what the preprocessing did, one line each.
    """

    t: np.ndarray
    s: np.ndarray
    delta: np.ndarray
    cycles: np.ndarray
    filled: np.ndarray
    notes: tuple[str, ...]

    @property
    def n_cycles(self) -> int:
        return int(self.cycles.shape[0])


def fill_dropouts(t: np.ndarray, x: np.ndarray, max_gap_s: float, name: str) -> np.ndarray:
    """Linear interpolation across interior NaN runs no longer than ``max_gap_s``."""
    bad = ~np.isfinite(x)
    if not bad.any():
        return x
    good = np.flatnonzero(~bad)
    edges = np.flatnonzero(np.diff(np.concatenate([[0], bad.view(np.int8), [0]])))
    for a, b in zip(edges[::2], edges[1::2], strict=True):
        if a == 0 or b == x.size:
            continue  # trimmed by the caller
        gap = t[b] - t[a - 1]
        if gap > max_gap_s:
            raise InputError(
                f"channel {name}: dropout of {gap:.3g} s at t={t[a]:.6g} s is longer than "
                f"the largest gap bridged ({max_gap_s:g} s)"
            )
    return np.interp(t, t[good], x[good])


def _local_median(x: np.ndarray, i: int, half: int) -> float:
    return float(np.median(x[max(0, i - half) : i + half + 1]))


def find_cycles(s: np.ndarray) -> tuple[np.ndarray, float, float]:
    """Cycles (start, peak, end indices) of a stroke signal; also its rest level and amplitude."""
    lo_q, hi_q = np.percentile(s, [1.0, 99.0])
    amp = hi_q - lo_q
    if not np.isfinite(amp) or amp <= 0:
        raise InputError("no strokes found: the shortening signal does not vary")
    up_th, dn_th, rest_th = lo_q + 0.6 * amp, lo_q + 0.4 * amp, lo_q + 0.1 * amp
    high = False
    rises, falls = [], []
    for i, v in enumerate(s):
        if not high and v > up_th:
            high = True
            rises.append(i)
        elif high and v < dn_th:
            high = False
            falls.append(i)
    cycles = []
    for k, r in enumerate(rises):
        prev_fall = max((f for f in falls if f < r), default=0)
        next_fall = next((f for f in falls if f > r), None)
        if next_fall is None:
            break  # the record ends during a contraction
        next_rise = next((q for q in rises if q > next_fall), s.size)
        start = prev_fall + int(np.argmin(s[prev_fall : r + 1]))
        peak = r + int(np.argmax(s[r : next_fall + 1]))
        end = next_fall + int(np.argmin(s[next_fall:next_rise]))
        if s[start] > rest_th or s[end] > rest_th:
            continue  # partial: does not start (or end) at rest
        if k == 0 and start == 0 and s[0] > lo_q + 0.05 * amp:
            continue
        cycles.append((start, peak, end))
    if not cycles:
        raise InputError("no complete stroke cycle (rest -> peak -> rest) found in the recording")
    return np.asarray(cycles, dtype=int), float(lo_q), float(amp)


def prepare(rec: Recording, max_gap_s: float = 0.5, use_measured_shortening: bool = False):
    """Clean a recording and find its cycles -> :class:`GaitSignals`."""
    notes = []
    t = rec.t
    chans = {"left": rec.left, "right": rec.right}
    if use_measured_shortening:
        if rec.shortening is None:
            raise InputError("the recording has no shortening channel")
        chans["shortening"] = rec.shortening
    finite = np.all([np.isfinite(v) for v in chans.values()], axis=0)
    first, last = np.flatnonzero(finite)[[0, -1]]
    if first > 0 or last < t.size - 1:
        notes.append(f"trimmed {first + t.size - 1 - last} samples with missing data at the ends")
    sl = slice(first, last + 1)
    t = t[sl]
    filled = ~finite[sl]
    clean = {k: fill_dropouts(t, v[sl], max_gap_s, k) for k, v in chans.items()}
    if filled.any():
        notes.append(f"bridged {int(filled.sum())} missing samples by linear interpolation")
    s_raw = clean["shortening"] if use_measured_shortening else clean["left"] - clean["right"]
    cycles, _, amp = find_cycles(s_raw)
    half = max(1, round(0.05 / max(float(np.median(np.diff(t))), 1e-12)))
    bounds = np.unique(np.concatenate([cycles[:, 0], cycles[:, 2]]))
    rest = np.array([_local_median(s_raw, i, half) for i in bounds])
    baseline = np.interp(t, t[bounds], rest)
    s = s_raw - baseline
    if np.ptp(rest) > 1e-3 * amp:
        notes.append(f"removed offset/drift of s: rest level varied by {np.ptp(rest):.3g} mm")
    right = clean["right"]
    delta = right - _local_median(right, int(cycles[0, 0]), half)
    if cycles[0, 0] > 0:
        notes.append(f"discarded {t[cycles[0, 0]] - t[0]:.3g} s before the first complete cycle")
    return GaitSignals(t, s, delta, cycles, filled, tuple(notes))
