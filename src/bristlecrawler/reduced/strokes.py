"""Shortening histories s(t) (mm) that drive the crawler's actuators.

The paper's stroke is ``s(t) = s_max sin^2(pi t / T)`` (Section 3). The reduced model is
rate-independent, so any monotone re-parametrisation of the same stroke (a triangle wave, a
recorded closed-loop actuator history) produces the same Delta(s); :class:`TriangleStroke`
exists to test exactly that. :class:`SampledStroke` takes an arbitrary recorded or designed
history, interpolated linearly between its samples.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from bristlecrawler._files import MAX_INPUT_BYTES, open_regular
from bristlecrawler.errors import InputError, positive

#: Largest time a history may hold, s (about 30 years).
MAX_TIME = 1e9


@dataclass(frozen=True)
class Sin2Stroke:
    """``s(t) = s_max sin^2(pi t / period)`` for ``0 <= t <= cycles * period``.

    Attributes:
        s_max: peak shortening s~ in mm (> 0).
        period: cycle duration T in s (> 0).
    """

    s_max: float
    period: float

    def __post_init__(self) -> None:
        object.__setattr__(self, "s_max", positive("s_max (peak shortening, mm)", self.s_max))
        object.__setattr__(self, "period", positive("period (s)", self.period))

    def __call__(self, t: np.ndarray) -> np.ndarray:
        return self.s_max * np.sin(np.pi * np.asarray(t, dtype=float) / self.period) ** 2

    def duration(self, cycles: int) -> float:
        return cycles * self.period

    def sample_times(self, cycles: int, samples_per_cycle: int) -> np.ndarray:
        """Uniform times, an even number per cycle, so every turning point is a sample."""
        n = 2 * max(1, (int(samples_per_cycle) + 1) // 2)
        return np.linspace(0.0, cycles * self.period, cycles * n + 1)


@dataclass(frozen=True)
class TriangleStroke(Sin2Stroke):
    """Piecewise-linear stroke with the same peaks and period as :class:`Sin2Stroke`."""

    def __call__(self, t: np.ndarray) -> np.ndarray:
        phase = np.mod(np.asarray(t, dtype=float) / self.period, 1.0)
        return self.s_max * (1.0 - np.abs(1.0 - 2.0 * phase))


@dataclass(frozen=True)
class SampledStroke:
    """A shortening history given by samples, interpolated linearly between them.

    Attributes:
        t: sample times in s, finite and strictly increasing.
        s: shortening at those times in mm, finite and >= 0.
        period: nominal cycle duration in s used to split results into cycles; when None,
            cycles are the excursions that start and end at the initial shortening.
    """

    t: np.ndarray
    s: np.ndarray
    period: float | None = None
    s_max: float = field(init=False)

    def __post_init__(self) -> None:
        t = np.asarray(self.t, dtype=float).ravel()
        s = np.asarray(self.s, dtype=float).ravel()
        if t.shape != s.shape:
            raise InputError(f"history: t has {t.size} samples but s has {s.size}")
        if t.size < 2:
            raise InputError("history: at least two samples are needed")
        if not np.all(np.isfinite(t)):
            raise InputError(f"history: non-finite time at sample {int(np.argmin(np.isfinite(t)))}")
        if not np.all(np.isfinite(s)):
            raise InputError(
                f"history: non-finite shortening at sample {int(np.argmin(np.isfinite(s)))}"
            )
        if np.any(np.abs(t) > MAX_TIME):
            i = int(np.argmax(np.abs(t) > MAX_TIME))
            raise InputError(f"history: time {t[i]:g} s at sample {i} is beyond +-{MAX_TIME:g} s")
        bad = np.flatnonzero(np.diff(t) <= 0.0)
        if bad.size:
            raise InputError(
                f"history: times must be strictly increasing (sample {int(bad[0]) + 1}: "
                f"t={t[bad[0] + 1]} after t={t[bad[0]]})"
            )
        if np.any(s < 0.0):
            i = int(np.argmax(s < 0.0))
            raise InputError(f"history: shortening must be >= 0 mm (sample {i}: s={s[i]})")
        if self.period is not None:
            positive("period (s)", self.period)
        t.setflags(write=False)
        s.setflags(write=False)
        object.__setattr__(self, "t", t)
        object.__setattr__(self, "s", s)
        object.__setattr__(self, "s_max", float(s.max()))

    def __call__(self, t: np.ndarray) -> np.ndarray:
        return np.interp(np.asarray(t, dtype=float) + self.t[0], self.t, self.s)

    def duration(self, cycles: int | None = None) -> float:
        return float(self.t[-1] - self.t[0])

    def sample_times(self, cycles: int | None = None, samples_per_cycle: int | None = None):
        """The history's own sample times, shifted to start at 0."""
        return self.t - self.t[0]


Stroke = Sin2Stroke | TriangleStroke | SampledStroke


def read_history_csv(path: str) -> SampledStroke:
    """Read a shortening history from a CSV file with a header and columns ``t`` (s), ``s`` (mm).

    Extra columns are ignored. Raises :class:`InputError` with one line on any problem.
    """
    import csv
    import os

    if not isinstance(path, str | os.PathLike):
        raise InputError(f"history must be a file name, got {path!r}")
    try:
        # Checked before reading: a FIFO would hang, a device or a huge file fill the memory.
        fd = open_regular(path, MAX_INPUT_BYTES)
    except FileNotFoundError:
        raise InputError(f"history file not found: {path}") from None
    except OSError as exc:
        raise InputError(f"cannot read history file {path}: {exc.strerror or exc}") from None
    try:
        # utf-8-sig: spreadsheet programs start a CSV with a byte-order mark.
        with open(fd, newline="", encoding="utf-8-sig") as fh:
            reader = csv.reader(
                row for row in fh if row.strip() and not row.lstrip().startswith("#")
            )
            header = next(reader, None)
            if header is None:
                raise InputError(f"history file {path} is empty")
            names = [h.strip().lower() for h in header]
            missing = [c for c in ("t", "s") if c not in names]
            if missing:
                # What the file holds is not quoted: the path may name a file the user
                # did not write (a scenario's actuation.history), even a secret one.
                raise InputError(
                    f"history file {path} lacks column(s) {', '.join(missing)} in its first "
                    f"row of {len(header)} cells; expected a header with 't' (s) and 's' (mm)"
                )
            it, is_ = names.index("t"), names.index("s")
            t, s = [], []
            for lineno, row in enumerate(reader, start=2):
                try:
                    t.append(float(row[it]))
                    s.append(float(row[is_]))
                except (ValueError, IndexError):
                    raise InputError(
                        f"history file {path}, data row {lineno - 1}: its t (s) and s (mm) "
                        "cells are not both numbers"
                    ) from None
    except UnicodeDecodeError:
        raise InputError(f"history file {path} is not a UTF-8 text CSV file") from None
    except csv.Error as exc:
        raise InputError(f"history file {path} is not a readable CSV file ({exc})") from None
    except OSError as exc:
        raise InputError(f"cannot read history file {path}: {exc.strerror or exc}") from None
    return SampledStroke(np.array(t), np.array(s))
