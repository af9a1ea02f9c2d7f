"""The reduced (one-dimensional) crawler of the paper's Fig. 9, generalised to N bristles.

A massless body carries N bristles at attachment points X_0 < X_1 < ... < X_{N-1} (mm). The
N-1 body segments between consecutive attachments have rest lengths ``segment_lengths`` and
are shortened by actuators. Bristle i is a linear spring of stiffness k_i (N/mm) between its
attachment and its tip x_i; the tip obeys the directional friction law with (F_p,i, F_n,i).
The paper's crawler is ``ReducedCrawler.two_bristle()``: L = 100 mm, k = 0.48 N/mm,
F_p = 0.456 N (so that F_p/k = 0.95 mm exactly, the value the paper uses; the paper rounds
F_p to 0.45 N).
"""

from __future__ import annotations

import warnings
from collections.abc import Mapping
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from bristlecrawler.errors import InputError
from bristlecrawler.reduced.friction import DirectionalFriction
from bristlecrawler.reduced.model import ReducedModel
from bristlecrawler.results.drag import summary_of
from bristlecrawler.results.keys import FN_N, FP_N, K_N_PER_MM

#: Paper values (Section 4): F_p/k = 0.95 mm, k = 0.48 N/mm, L = 100 mm, s~ = 20 mm, T = 20 s.
PAPER_K = 0.48
PAPER_FP = 0.95 * PAPER_K
PAPER_LENGTH = 100.0
PAPER_S_MAX = 20.0
PAPER_PERIOD = 20.0
PAPER_CYCLES = 5
#: F_n is not identifiable from the two-bristle gait (any F_n > F_p gives the same motion);
#: the default anisotropy F_n / F_p used when none is given. It matters for N >= 3 bristles.
DEFAULT_FN_OVER_FP = 3.0


def _as_vector(name: str, value, n: int) -> np.ndarray:
    arr = np.asarray(value, dtype=float)
    if arr.ndim == 0:
        arr = np.full(n, float(arr))
    if arr.shape != (n,):
        raise InputError(f"{name} must be a scalar or have {n} entries, got shape {arr.shape}")
    if not np.all(np.isfinite(arr)) or np.any(arr <= 0.0):
        raise InputError(f"{name} must be positive and finite, got {arr.tolist()}")
    arr.setflags(write=False)
    return arr


@dataclass(frozen=True)
class ReducedCrawler(ReducedModel):
    """N-bristle reduced crawler: the paper's law (eq. 4.1), one F_p and F_n per bristle.

    Attributes:
        k: bristle stiffnesses, N/mm, shape (N,).
        fp: along-the-grain resistances F_p, N, shape (N,).
        fn: against-the-grain resistances F_n, N, shape (N,), fn >= fp.
        segment_lengths: rest lengths of the N-1 body segments, mm.
    """

    name: ClassVar[str] = "paper"

    k: np.ndarray
    fp: np.ndarray
    fn: np.ndarray
    segment_lengths: np.ndarray

    def __post_init__(self) -> None:
        seg = np.atleast_1d(np.asarray(self.segment_lengths, dtype=float))
        if seg.ndim != 1 or seg.size < 1:
            raise InputError("a crawler needs at least 2 bristles (1 body segment)")
        n = seg.size + 1
        object.__setattr__(self, "segment_lengths", _as_vector("segment length (mm)", seg, n - 1))
        object.__setattr__(self, "k", _as_vector("k (bristle stiffness, N/mm)", self.k, n))
        object.__setattr__(self, "fp", _as_vector("F_p (N)", self.fp, n))
        object.__setattr__(self, "fn", _as_vector("F_n (N)", self.fn, n))
        if np.any(self.fn < self.fp):
            i = int(np.argmax(self.fn < self.fp))
            raise InputError(
                f"F_n must be >= F_p (bristle {i}: F_n={self.fn[i]} < F_p={self.fp[i]})"
            )

    @classmethod
    def uniform(
        cls,
        n_bristles: int = 2,
        length: float = PAPER_LENGTH,
        k: float = PAPER_K,
        fp: float = PAPER_FP,
        fn: float | None = None,
    ) -> ReducedCrawler:
        """N identical bristles evenly spaced over a body of length ``length`` (mm).

        ``fn`` defaults to ``DEFAULT_FN_OVER_FP * fp``.
        """
        if int(n_bristles) != n_bristles or n_bristles < 2:
            raise InputError(f"a crawler needs at least 2 bristles, got {n_bristles}")
        length = float(length)
        if not np.isfinite(length) or length <= 0:
            raise InputError(f"body length must be positive (mm), got {length}")
        fn = DEFAULT_FN_OVER_FP * fp if fn is None else fn
        n = int(n_bristles)
        return cls(k=k, fp=fp, fn=fn, segment_lengths=np.full(n - 1, length / (n - 1)))

    @classmethod
    def two_bristle(cls, **kwargs) -> ReducedCrawler:
        """The paper's crawler (defaults) or a two-bristle crawler with the given values."""
        return cls.uniform(n_bristles=2, **kwargs)

    @classmethod
    def from_drag(
        cls,
        drag,
        n_bristles: int = 2,
        length: float = PAPER_LENGTH,
        *,
        segment_lengths=None,
        model: str = "paper",
        start_mm: float = 0.0,
    ):
        """The crawler whose bristles all have a drag test's k, F_p and F_n.

        Args:
            drag: a drag test's :class:`~bristlecrawler.results.drag.DragSummary`,
                its result (anything with ``summarize()`` or ``summary()``, such as
                ``bristlecrawler.crawler.drag.DragResult``) or its summary mapping: reads
                k (first-loading slope), F_p and F_n; a sequence of them gives each
                bristle its own.
            n_bristles: number of bristles, spread evenly over ``length`` (mm), unless
                ``segment_lengths`` (mm, N-1 values) places them.

        A bristle that resists both ways alike (alpha = 0, F_n within the scatter of F_p)
        gets F_n = F_p. A drag test that never slid one way has no value for it: refused.

        ``model = "texture"`` (with ``start_mm``) is deprecated: ``TexturedCrawler.from_drag``
        (:mod:`bristlecrawler.reduced.textured`) builds the crawler on the drag test's
        texture law.
        """
        if model not in ("paper", "texture"):
            raise InputError(f"reduced model must be paper or texture, got {model!r}")
        many = isinstance(drag, list | tuple)
        if model == "texture":
            warnings.warn(
                "ReducedCrawler.from_drag(model='texture') is deprecated: use "
                "TexturedCrawler.from_drag",
                DeprecationWarning,
                stacklevel=2,
            )
            return ReducedModel.registered["texture"].from_drag(
                drag, n_bristles, length, segment_lengths=segment_lengths, start_mm=start_mm
            )
        values = [_drag_values(d) for d in (drag if many else [drag])]
        if many:
            n_bristles = len(values)
        if segment_lengths is None:
            if int(n_bristles) != n_bristles or n_bristles < 2:
                raise InputError(f"a crawler needs at least 2 bristles, got {n_bristles}")
            segment_lengths = np.full(int(n_bristles) - 1, float(length) / (n_bristles - 1))
        k, fp, fn = (np.array([v[j] for v in values]) for j in range(3))
        if not many:  # one test for every bristle
            k, fp, fn = k[0], fp[0], fn[0]
        return cls(k=k, fp=fp, fn=np.maximum(fn, fp), segment_lengths=segment_lengths)

    @property
    def n_bristles(self) -> int:
        return int(self.k.size)

    @property
    def length(self) -> float:
        """Rest distance between the first and the last bristle, mm."""
        return float(self.segment_lengths.sum())

    def solve(self, t, shortening, cycle_bounds=None):
        """See :meth:`ReducedModel.solve` (:func:`bristlecrawler.reduced.solve`)."""
        from bristlecrawler.reduced.solver import solve

        return solve(self, t, shortening, cycle_bounds)

    def paper_crawler(self) -> ReducedCrawler:
        """Itself: the paper's model."""
        return self

    def texture_laws(self) -> None:
        """None: the paper's law does not depend on the tip's position."""
        return None

    def friction(self, i: int) -> DirectionalFriction:
        """The friction law of bristle ``i``."""
        return DirectionalFriction(float(self.fp[i]), float(self.fn[i]))

    def check_stroke(self, max_shortening: np.ndarray | float) -> None:
        """Refuse segment shortenings that would make a segment vanish or invert."""
        s = np.broadcast_to(np.asarray(max_shortening, dtype=float), self.segment_lengths.shape)
        bad = np.flatnonzero(s >= self.segment_lengths)
        if bad.size:
            j = int(bad[0])
            raise InputError(
                f"peak shortening {s[j]:g} mm must be smaller than the segment length "
                f"{self.segment_lengths[j]:g} mm (segment {j})"
            )


def _drag_values(drag) -> tuple[float, float, float]:
    """(k, F_p, F_n) of a drag test's summary, refused with the missing one's name."""
    names = {K_N_PER_MM: "k", FP_N: "F_p", FN_N: "F_n"}
    if isinstance(drag, Mapping):
        for key, name in names.items():
            if key not in drag:
                raise InputError(f"the drag test gives no {name} ({key})")
    summary = summary_of(drag)
    values = {K_N_PER_MM: summary.k, FP_N: summary.fp, FN_N: summary.fn}
    out = []
    for key, name in names.items():
        v = values[key]
        if not (np.isfinite(v) and v > 0):
            how = {
                "k": "the tip never stuck before it slipped",
                "F_p": "it never slid along the grain",
                "F_n": "it never slid against the grain (run direction cycle)",
            }
            raise InputError(f"the drag test gives no {name}: {how[name]} (got {v})")
        out.append(v)
    return out[0], out[1], out[2]
