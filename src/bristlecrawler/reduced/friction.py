"""Directional (ratchet-like) friction law of the paper, eq. (4.1).

The horizontal force ``F`` that the substrate exerts, through a bristle, on the crawler is

    F = +F_n            if  xdot < 0   (sliding against the grain, i.e. backwards),
    F in [-F_p, F_n]    if  xdot = 0   (stick: any force in the closed interval),
    F = -F_p            if  xdot > 0   (sliding along the grain, i.e. forwards),

with ``F_n >= F_p > 0``. It is the subdifferential of the positively homogeneous dissipation
potential ``R(v) = F_p v+ + F_n v-`` (``v+ = max(v, 0)``, ``v- = max(-v, 0)``): ``-F in dR(v)``.
The same object describes the effective law extracted from finite-element drag tests.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from bristlecrawler.errors import InputError, positive


@dataclass(frozen=True)
class DirectionalFriction:
    """Rate-independent directional friction law of one bristle tip.

    Attributes:
        fp: resistance to sliding along the grain (forwards), F_p, in N; > 0.
        fn: resistance to sliding against the grain (backwards), F_n, in N; >= fp.
    """

    fp: float
    fn: float

    def __post_init__(self) -> None:
        fp = positive("F_p (fp)", self.fp)
        fn = positive("F_n (fn)", self.fn)
        if fn < fp:
            raise InputError(f"F_n must be >= F_p for a directional law, got F_n={fn} < F_p={fp}")
        object.__setattr__(self, "fp", fp)
        object.__setattr__(self, "fn", fn)

    @classmethod
    def with_ratio(cls, fp: float, ratio: float) -> DirectionalFriction:
        """Law with ``F_n = ratio * F_p`` (ratio >= 1, dimensionless)."""
        return cls(fp=fp, fn=float(ratio) * float(fp))

    @property
    def anisotropy(self) -> float:
        """F_n / F_p (dimensionless, >= 1)."""
        return self.fn / self.fp

    @property
    def stick_interval(self) -> tuple[float, float]:
        """Closed interval of admissible forces at rest, (-F_p, F_n), in N."""
        return (-self.fp, self.fn)

    def is_admissible(self, force: np.ndarray | float, tol: float = 0.0) -> np.ndarray:
        """True where ``-F_p - tol <= force <= F_n + tol`` (force in N)."""
        f = np.asarray(force, dtype=float)
        return (f >= -self.fp - tol) & (f <= self.fn + tol)

    def force(
        self, velocity: np.ndarray | float, stick_force: np.ndarray | float = np.nan
    ) -> np.ndarray:
        """Force (N) for a sliding velocity (mm/s), eq. (4.1).

        At ``velocity == 0`` the law is set-valued; the force there is ``stick_force``
        projected onto the stick interval (NaN, meaning "undetermined", by default).
        """
        v = np.asarray(velocity, dtype=float)
        at_rest = np.clip(np.asarray(stick_force, dtype=float), -self.fp, self.fn)
        return np.where(v > 0.0, -self.fp, np.where(v < 0.0, self.fn, at_rest))

    def dissipation(self, slip: np.ndarray | float) -> np.ndarray:
        """Energy (mJ) dissipated by a monotone slip increment (mm): ``F_p s+ + F_n s-``."""
        d = np.asarray(slip, dtype=float)
        return self.fp * np.maximum(d, 0.0) + self.fn * np.maximum(-d, 0.0)
