"""A recording of the two laser displacement transducers (paper Section 2).

The transducers measure the displacements of the left (rear) and right (front) ends of the
crawler, in mm, positive in the direction of motion, sampled at 100 S/s on the prototype's
cRIO. With both ends' displacements the paper's quantities follow: the shortening
``s(t) = left(t) - right(t)`` (the body length is L + right - left) and the advance of the
front end ``Delta(t) = right(t)`` (both up to the offsets and drift that
:mod:`bristlecrawler.experiment.preprocess` removes).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from bristlecrawler.errors import InputError

#: Default sample rate of the prototype's acquisition (NI-9215 on a cRIO-9082), samples/s.
DEFAULT_RATE_HZ = 100.0

#: Largest magnitude a channel may hold (its unit): a transducer reading beyond this is a
#: corrupt cell or a wrong unit, and would carry through the fit to absurd parameters.
CHANNEL_LIMITS = {
    "time": 1e9,
    "left": 1e5,
    "right": 1e5,
    "shortening": 1e5,
    "force": 1e6,
    "current": 1e4,
}
CHANNEL_UNITS = {
    "time": "s",
    "left": "mm",
    "right": "mm",
    "shortening": "mm",
    "force": "N",
    "current": "A",
}


def _check_range(source: str, name: str, arr: np.ndarray) -> None:
    limit = CHANNEL_LIMITS[name]
    big = np.flatnonzero(np.abs(np.nan_to_num(arr, nan=0.0)) > limit)
    if big.size:
        i = int(big[0])
        raise InputError(
            f"{source or 'recording'}: channel {name} sample {i} is {arr[i]:.12g} "
            f"{CHANNEL_UNITS[name]}, beyond +-{limit:g} {CHANNEL_UNITS[name]}"
        )


def _channel(name: str, values, n: int | None) -> np.ndarray:
    arr = np.asarray(values, dtype=float).ravel()
    if n is not None and arr.size != n:
        raise InputError(f"channel {name} has {arr.size} samples, expected {n}")
    arr.setflags(write=False)
    return arr


@dataclass(frozen=True)
class Recording:
    """Synchronous channels of one trial.

    Attributes:
        t: time, s, finite and strictly increasing.
        left: displacement of the left (rear) end, mm (NaN where the sensor dropped out).
        right: displacement of the right (front) end, mm (NaN where it dropped out).
        current: actuator current, A (optional).
        shortening: measured shortening s(t), mm (optional; else left - right is used).
        force: connector (actuator) force, N (optional).
        source: where the data came from (file name).
    """

    t: np.ndarray
    left: np.ndarray
    right: np.ndarray
    current: np.ndarray | None = None
    shortening: np.ndarray | None = None
    force: np.ndarray | None = None
    source: str = ""
    extra: dict = field(default_factory=dict)

    def __post_init__(self) -> None:
        t = _channel("time", self.t, None)
        n = t.size
        _check_range(self.source, "time", t)
        if n < 10:
            raise InputError(f"{self.source or 'recording'}: only {n} samples, need at least 10")
        if not np.all(np.isfinite(t)):
            raise InputError(f"{self.source or 'recording'}: time channel has non-finite values")
        bad = np.flatnonzero(np.diff(t) <= 0)
        if bad.size:
            raise InputError(
                f"{self.source or 'recording'}: time is not strictly increasing at sample "
                f"{int(bad[0]) + 1} (t={t[bad[0] + 1]:g} s)"
            )
        object.__setattr__(self, "t", t)
        for name in ("left", "right"):
            arr = _channel(name, getattr(self, name), n)
            if np.isfinite(arr).sum() < 10:
                raise InputError(f"{self.source or 'recording'}: channel {name} has no usable data")
            _check_range(self.source, name, arr)
            object.__setattr__(self, name, arr)
        for name in ("current", "shortening", "force"):
            if getattr(self, name) is not None:
                arr = _channel(name, getattr(self, name), n)
                _check_range(self.source, name, arr)
                object.__setattr__(self, name, arr)

    @property
    def rate_hz(self) -> float:
        """Median sample rate, samples/s."""
        return float(1.0 / np.median(np.diff(self.t)))

    @property
    def duration(self) -> float:
        return float(self.t[-1] - self.t[0])
