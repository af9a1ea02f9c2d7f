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

from dataclasses import dataclass

import numpy as np

from bristlecrawler.errors import InputError
from bristlecrawler.reduced.friction import DirectionalFriction

#: Paper values (Section 4): F_p/k = 0.95 mm, k = 0.48 N/mm, L = 100 mm, s~ = 20 mm, T = 20 s.
PAPER_K = 0.48
PAPER_FP = 0.95 * PAPER_K
PAPER_LENGTH = 100.0
PAPER_S_MAX = 20.0
PAPER_PERIOD = 20.0
PAPER_CYCLES = 5
#: F_n is not identifiable from the two-bristle gait (any F_n >= F_p gives the same motion);
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
class ReducedCrawler:
    """N-bristle reduced crawler.

    Attributes:
        k: bristle stiffnesses, N/mm, shape (N,).
        fp: along-the-grain resistances F_p, N, shape (N,).
        fn: against-the-grain resistances F_n, N, shape (N,), fn >= fp.
        segment_lengths: rest lengths of the N-1 body segments, mm.
    """

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

    @property
    def n_bristles(self) -> int:
        return int(self.k.size)

    @property
    def length(self) -> float:
        """Rest distance between the first and the last bristle, mm."""
        return float(self.segment_lengths.sum())

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
