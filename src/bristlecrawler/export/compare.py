"""The numbers a drag test gives, read the same way from any FE code's series.

A drag test's series, whoever computed it, is the carriage's travel x (mm), the
horizontal force the carriage applies (N, +x) and the substrate's force on the bristle
(N, (x, y)). From it:

* the **stiffness before sliding** (N/mm): the least-squares slope of the force over the
  travel while it climbs from 10 % to 40 % of the way from its start to the sliding force
  mu N (N: the vertical contact force), the bristle's tip held by friction;
* the **sliding force on a flat** (N): the mean force while the contact force leans at the
  friction angle (|f_x| / f_y within 1 % of mu), the tip sliding on a land or a groove's
  bottom; quasi-statically it is mu N;
* the **peak force** (N): the largest force of the leg, where a groove's wall or its
  corner holds the bristle until it climbs over.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class DragSeries:
    """One leg of a drag test: travel ``x`` (mm), ``force`` (N) and ``contact`` (M, 2) (N)."""

    x: np.ndarray
    force: np.ndarray
    contact: np.ndarray

    @property
    def normal(self) -> float:
        """The vertical contact force, its median over the leg, N."""
        return float(np.median(self.contact[:, 1]))


def stick_stiffness(s: DragSeries, sliding: float, lo: float = 0.1, hi: float = 0.4) -> float:
    """Slope (N/mm) of the force over the travel from ``lo`` to ``hi`` of the way from its
    first value to ``sliding`` (N), on the first rise; NaN with fewer than 3 samples."""
    f0 = s.force[0]
    span = sliding - f0
    if not span > 0:
        return math.nan
    reached = np.flatnonzero(s.force >= f0 + hi * span)
    end = reached[0] if reached.size else len(s.force)
    f, x = s.force[:end], s.x[:end]
    keep = f >= f0 + lo * span
    if keep.sum() < 3:
        return math.nan
    return float(np.polyfit(x[keep], f[keep], 1)[0])


def flat_sliding(s: DragSeries, mu: float, tol: float = 0.01) -> tuple[float, int]:
    """Mean force (N) and sample count while the contact force leans at the friction
    angle (sliding on a flat part of the surface); (NaN, 0) if it never does."""
    cx, cy = s.contact[:, 0], s.contact[:, 1]
    with np.errstate(divide="ignore", invalid="ignore"):
        lean = np.abs(cx) / cy
    on = (cy > 0) & (np.abs(lean - mu) <= tol * mu) & (s.force > 0)
    if not on.any():
        return math.nan, 0
    return float(np.mean(s.force[on])), int(on.sum())


def peak(s: DragSeries) -> tuple[float, float]:
    """The largest force of the leg (N) and the travel where it occurs (mm)."""
    i = int(np.argmax(s.force))
    return float(s.force[i]), float(s.x[i])


@dataclass(frozen=True)
class Row:
    """One quantity of the comparison, with both codes' values and the expected one."""

    quantity: str
    unit: str
    toolkit: float
    calculix: float
    expected: float = math.nan
    note: str = ""

    @property
    def difference(self) -> float:
        """CalculiX against the toolkit, relative."""
        return (self.calculix - self.toolkit) / abs(self.toolkit) if self.toolkit else math.nan

    def to_dict(self) -> dict:
        return {
            "quantity": self.quantity,
            "unit": self.unit,
            "toolkit": self.toolkit,
            "calculix": self.calculix,
            "expected": self.expected,
            "relative_difference": self.difference,
            "note": self.note,
        }


def compare(flat_toolkit, flat_calculix, groove_toolkit, groove_calculix, mu: float) -> list[Row]:
    """The rows of the cross-check: stiffness and sliding force from the legs on a flat,
    the peak force from the legs over a groove (None: the design has no grooves)."""
    n_t, n_c = flat_toolkit.normal, flat_calculix.normal
    ft, count_t = flat_sliding(flat_toolkit, mu)
    fc, count_c = flat_sliding(flat_calculix, mu)
    rows = [
        Row(
            "stiffness before sliding",
            "N/mm",
            stick_stiffness(flat_toolkit, mu * n_t),
            stick_stiffness(flat_calculix, mu * n_c),
            note="on a flat, 10-40 % of the rise to mu N",
        ),
        Row(
            "sliding force on a flat",
            "N",
            ft,
            fc,
            expected=mu * n_t,
            note=f"mu N = {mu:g} x {n_t:.4g} N; {count_t} and {count_c} samples",
        ),
        Row("vertical contact force", "N", n_t, n_c, note="the load and the bristle's weight"),
    ]
    if groove_toolkit is not None:
        pt, xt = peak(groove_toolkit)
        pc, xc = peak(groove_calculix)
        rows.append(
            Row(
                "peak force at a groove's wall",
                "N",
                pt,
                pc,
                note=f"from a groove's middle; at travel {xt:.3g} and {xc:.3g} mm",
            )
        )
    return rows
