"""The texture law of a drag test: the bristle's resistance over its tip's position.

From a drag test that slides along and against the grain over whole pitches
(``DragTest(direction="cycle")``) this reads the reduced model's
:class:`~bristlecrawler.results.texture.TextureLaw`:

* k: the slope of the carriage's force over its travel while the FE tip sticks, pooled
  over every stick phase of the test (each with its own offset): the spring between the
  carriage and a held tip. The first-loading secant (``k_N_per_mm`` of the summary)
  depends on where in a pitch the tip starts (1.38 N/mm on 2 mm grooves, 0.23 N/mm on
  3 mm grooves, where the tip starts on a land and slides early); a spring to a tip
  should not.
* the reduced tip: the point that spring puts behind the carriage,
  ``xi = x_c + offset - F / k``, with the offset that starts it at the FE tip node. On this
  coordinate the reduced model replays the drag test: where the FE force follows a stable
  branch, the spring with this tip carries the same force at the same carriage travel.
  (The FE tip node itself is no such point: on grooves the tip flies over a groove while
  the bristle's face rides a land edge.)
* F_p(x), F_n(x): in each of ``cells`` equal cells of the pitch (substrate coordinates, mod
  pitch), the force over the reduced tip's travel while it slides forwards (backwards)
  quasi-statically, weighted by that travel. Steps where the tip outruns the carriage
  (a snap) are left out; a cell crossed only in snaps gets the smallest resistance of its
  direction (it held the tip no more than any cell it slid through).
"""

from __future__ import annotations

import math

import numpy as np

from bristlecrawler.errors import InputError
from bristlecrawler.results.texture import TextureLaw
from bristlecrawler.states import ContactState

#: Cells per pitch of a texture law read from a drag test.
DEFAULT_CELLS = 16
#: Resistance of a cell that holds nothing, N (positive: the law needs one).
_NOTHING = 1e-6
#: A step in which the reduced tip moves more than this many times the carriage is a snap
#: (the force falling faster than k/2 per mm of travel): its force is the dynamics of the
#: jump, not a resistance, and is left out.
_SNAP = 2.0


def stick_stiffness(result, shortest: int = 4) -> float:
    """dF/dx_c (N/mm) pooled over the runs of at least ``shortest`` samples in which the
    FE tip sticks (least squares, an offset per run); NaN without any."""
    stick = np.asarray(result.tip_state) == ContactState.STICK
    edges = np.flatnonzero(np.diff(np.concatenate([[0], stick.astype(int), [0]])))
    sxx = sxf = 0.0
    for a, b in zip(edges[::2], edges[1::2], strict=True):
        if b - a < shortest:
            continue
        x, f = result.x[a:b], result.force_x[a:b]
        dx = x - x.mean()
        sxx += float(dx @ dx)
        sxf += float(dx @ (f - f.mean()))
    return sxf / sxx if sxx > 0 else math.nan


def reduced_tip(result, k: float) -> np.ndarray:
    """The reduced tip's position ``x_c + offset - F / k`` (mm) at every sample."""
    offset = result.tip[0, 0] - result.x[0] + result.force_x[0] / k
    return result.x + offset - result.force_x / k


def _per_cell(result, xi, direction: int, cells: int, origin: float) -> np.ndarray | None:
    """Travel-weighted mean force (magnitude, N) per cell while the reduced tip moves in
    ``direction``, after each leg's first slip; None without any such travel."""
    pitch = result.pitch
    work, travel = np.zeros(cells), np.zeros(cells)
    for leg, (_, b, d) in enumerate(result.legs):
        k0 = result.first_slip(leg)
        if d != direction or k0 is None or b - k0 < 2:
            continue
        x, f = xi[k0 : b + 1], d * result.force_x[k0 : b + 1]
        dx = d * np.diff(x)
        carriage = np.abs(np.diff(result.x[k0 : b + 1]))
        mid = 0.5 * (x[1:] + x[:-1])
        fm = 0.5 * (f[1:] + f[:-1])
        keep = (dx > 0) & (dx <= _SNAP * carriage)
        j = np.floor(((mid - origin) % pitch) / (pitch / cells)).astype(int) % cells
        work += np.bincount(j[keep], weights=(fm * dx)[keep], minlength=cells)
        travel += np.bincount(j[keep], weights=dx[keep], minlength=cells)
    if not travel.any():
        return None
    mean = np.where(travel > 0, work / np.maximum(travel, 1e-300), np.nan)
    mean = np.where(np.isfinite(mean), mean, np.nanmin(mean))
    return np.maximum(mean, _NOTHING)


def texture_law(result, cells: int = DEFAULT_CELLS, origin: float = 0.0) -> TextureLaw:
    """The :class:`TextureLaw` of a drag result (``crawler.drag.DragResult``); refused
    (InputError) when the test did not slide both ways or gives no stiffness."""
    if not (isinstance(cells, int) and cells >= 1):
        raise InputError(f"texture cells must be a positive integer, got {cells!r}")
    k = stick_stiffness(result)
    if not (math.isfinite(k) and k > 0):
        raise InputError("the drag test gives no stiffness: its tip never stuck")
    xi = reduced_tip(result, k)
    laws = []
    for d, name in ((+1, "along"), (-1, "against")):
        law = _per_cell(result, xi, d, cells, origin)
        if law is None:
            raise InputError(f"the drag test never slid {name} the grain: run direction cycle")
        laws.append(law)
    offset = float(xi[0] - result.x[0])
    return TextureLaw(result.pitch, laws[0], laws[1], k, origin, offset)
