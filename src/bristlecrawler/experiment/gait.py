"""Gait analysis: per-cycle advance and stick/slip transitions from slope changes.

Along each stroke branch Delta(s) is piecewise linear in the reduced model (slope -1/2 while
both tips stick, 0 or -1 while one slides), so a transition shows as a kink. Each branch is
fitted with a continuous two-piece linear function whose breakpoint is chosen by least
squares (scan, then refine); a kink whose F statistic against a straight line is below 25
is reported as absent.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from bristlecrawler.experiment.preprocess import GaitSignals


@dataclass(frozen=True)
class Transition:
    """A stick/slip transition detected on one branch.

    ``branch`` is "contraction" or "extension"; ``s`` (mm) and ``t`` (s) locate the kink;
    ``slope_before``/``slope_after`` are dDelta/ds on either side (in the branch's direction
    of travel).
    """

    cycle: int
    branch: str
    t: float
    s: float
    slope_before: float
    slope_after: float

    def as_dict(self) -> dict:
        return dict(self.__dict__)


def _two_piece_sse(s: np.ndarray, d: np.ndarray, sb: float) -> tuple[float, np.ndarray]:
    """Least-squares continuous two-piece linear fit with breakpoint ``sb``."""
    A = np.column_stack([np.ones_like(s), np.minimum(s - sb, 0.0), np.maximum(s - sb, 0.0)])
    coef, *_ = np.linalg.lstsq(A, d, rcond=None)
    r = d - A @ coef
    return float(r @ r), coef


def detect_kink(s: np.ndarray, d: np.ndarray) -> tuple[float, float, float] | None:
    """Breakpoint s* and the slopes below/above it, or None when no kink is supported."""
    if s.size < 8:
        return None
    lo, hi = np.percentile(s, [3, 97])
    grid = np.linspace(lo, hi, 120)
    sse = np.array([_two_piece_sse(s, d, g)[0] for g in grid])
    j = int(np.argmin(sse))
    a, b = grid[max(j - 1, 0)], grid[min(j + 1, grid.size - 1)]
    for _ in range(40):  # golden-section refinement around the best grid point
        m1, m2 = a + 0.382 * (b - a), a + 0.618 * (b - a)
        if _two_piece_sse(s, d, m1)[0] < _two_piece_sse(s, d, m2)[0]:
            b = m2
        else:
            a = m1
    sb = 0.5 * (a + b)
    sse2, coef = _two_piece_sse(s, d, sb)
    A1 = np.column_stack([np.ones_like(s), s])
    c1, *_ = np.linalg.lstsq(A1, d, rcond=None)
    sse1 = float(np.sum((d - A1 @ c1) ** 2))
    dof = max(s.size - 4, 1)
    # F statistic of the two extra parameters (breakpoint, second slope); 25 is deliberately
    # strict so that noise and smooth curvature are not reported as transitions.
    if sse2 > 0 and ((sse1 - sse2) / 2.0) / (sse2 / dof) < 25.0:
        return None
    return float(sb), float(coef[1]), float(coef[2])


def transitions(sig: GaitSignals) -> list[Transition]:
    """Stick/slip transitions on every branch of every cycle."""
    out = []
    for n, (i0, ip, i1) in enumerate(sig.cycles):
        for branch, sl in (("contraction", slice(i0, ip + 1)), ("extension", slice(ip, i1 + 1))):
            s, d, t = sig.s[sl], sig.delta[sl], sig.t[sl]
            kink = detect_kink(s, d)
            if kink is None:
                continue
            sb, below, above = kink
            before, after = (below, above) if branch == "contraction" else (above, below)
            k = int(np.argmin(np.abs(s - sb)))
            out.append(Transition(n + 1, branch, float(t[k]), sb, before, after))
    return out


def per_cycle_advance(sig: GaitSignals) -> np.ndarray:
    """Advance of the front end over each cycle, mm."""
    return np.array([sig.delta[i1] - sig.delta[i0] for i0, _, i1 in sig.cycles])
