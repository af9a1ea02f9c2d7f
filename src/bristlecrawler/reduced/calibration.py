"""Calibration of the reduced model from a measured gait, as in the paper's Section 4.

Kinematics alone fix ``c = F_p/k``: the net advance after n cycles of a stroke s~ is
``A = n s~ - (4n - 1) c`` (regime 3, ``A >= s~/4``) or ``A = s~/2 - c`` (regime 2,
``0 < A < s~/4``). The actuator work over the same cycles then fixes F_p, and k = F_p / c.
Paper: 82 mm, 5 cycles, s~ = 20 mm -> F_p/k = 0.947 mm; 75 mJ -> F_p = 0.455 N, k = 0.480 N/mm.
F_n cannot be identified from a two-bristle breathing gait (every F_n > F_p gives the same
motion).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from bristlecrawler.errors import InputError
from bristlecrawler.reduced import closed_form as cf
from bristlecrawler.results import keys

#: Bounds of the measured inputs: stroke (mm), cycles, work (mJ). Beyond them the numbers
#: are not a crawler's, and the closed forms overflow.
MAX_S = 1e4
MAX_CYCLES = 100_000
MAX_WORK = 1e6


@dataclass(frozen=True)
class Calibration:
    """Result of :func:`calibrate`.

    Attributes:
        fp_over_k_mm: F_p / k, mm.
        regime: 2 or 3 (see :mod:`bristlecrawler.reduced.closed_form`).
        fp_N: F_p in N (None without a work measurement).
        k_N_per_mm: k in N/mm (None without a work measurement).
    """

    fp_over_k_mm: float
    regime: int
    fp_N: float | None = None
    k_N_per_mm: float | None = None

    def as_dict(self) -> dict:
        out = {"fp_over_k_mm": self.fp_over_k_mm, "regime": self.regime}
        if self.fp_N is not None:
            out |= {keys.FP_N: self.fp_N, keys.K_N_PER_MM: self.k_N_per_mm}
        return out


def calibrate(s_max: float, cycles: int, advance: float, work: float | None = None) -> Calibration:
    """Invert the closed form: F_p/k from the advance, and F_p, k from the work.

    Args:
        s_max: peak shortening s~ of the stroke, mm (> 0).
        cycles: number of full cycles n (>= 1) over which advance and work were measured.
        advance: net advance of the front end after n cycles, mm (0 < advance < n s~).
        work: actuator work over the n cycles, mJ (> 0), optional.
    """
    s, a = float(s_max), float(advance)
    if not np.isfinite(s) or s <= 0 or s > MAX_S:
        raise InputError(f"s_max must be a positive number of mm up to {MAX_S:g}, got {s_max}")
    if int(cycles) != cycles or not 1 <= cycles <= MAX_CYCLES:
        raise InputError(f"cycles must be an integer from 1 to {MAX_CYCLES}, got {cycles}")
    n = int(cycles)
    if not np.isfinite(a):
        raise InputError(f"advance must be finite, got {advance}")
    if a <= 0:
        raise InputError(
            f"advance {a:g} mm is not positive: a two-bristle breathing crawler never moves "
            f"backwards, and zero advance only says F_p/k >= s_max/2 = {s / 2:g} mm"
        )
    if a >= n * s:
        raise InputError(
            f"advance {a:g} mm must be smaller than cycles * s_max = {n * s:g} mm "
            "(equality would need rigid bristles)"
        )
    if a > s / 4:
        c, reg = (n * s - a) / (4 * n - 1), cf.STEADY_SLIDING
    else:
        c, reg = s / 2 - a, cf.FIRST_CONTRACTION_ONLY
    if work is None:
        return Calibration(float(c), int(reg))
    w = float(work)
    if not np.isfinite(w) or w <= 0 or w > MAX_WORK:
        raise InputError(f"work must be a positive number of mJ up to {MAX_WORK:g}, got {work}")
    if reg == cf.STEADY_SLIDING:
        fp = w / (c + 2 * (s - 3 * c) + 2 * (n - 1) * (s - 4 * c))
        k = fp / c
    else:
        k = w / (s**2 / 4 - c**2)
        fp = k * c
    return Calibration(float(c), int(reg), float(fp), float(k))
