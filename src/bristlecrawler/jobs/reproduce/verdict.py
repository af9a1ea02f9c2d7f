"""The verdict on a claim of no advance ("no appreciable net advancement" at alpha = 0)
from cycles measured at several starting places: an equivalence test, not a comparison
of a mean with a tolerance.

With the mean advance per cycle and its standard error over ``n`` places, the two-sided
95 % confidence interval (Student's t with ``n - 1`` degrees of freedom) is the range of
drifts the data do not exclude. Within ``±tol`` entirely, the data show that any drift is
below the tolerance: *agrees*. Outside it entirely: *differs*. Otherwise *inconclusive*:
the data cannot tell, and the interval's farthest end is the smallest drift they do
exclude; whether the interval holds 0 says whether they are consistent with no advance.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

LEVEL = 0.95


@dataclass(frozen=True)
class NullVerdict:
    """verdict: ``agrees``, ``differs`` or ``inconclusive``; low, high: the confidence
    interval of the mean (None with fewer than two finite values); excluded: the drift
    beyond which the data exclude the mean, ``max(|low|, |high|)``; reason: one sentence."""

    verdict: str
    mean: float | None
    sem: float | None
    low: float | None
    high: float | None
    excluded: float | None
    reason: str


def no_advance_verdict(values: Sequence[float], tol: float, unit: str = "mm") -> NullVerdict:
    """The verdict on "no advance" from ``values`` (one per starting place) against the
    tolerance ``tol`` (> 0), in ``unit``."""
    from scipy import stats

    x = [float(v) for v in values if v is not None and math.isfinite(v)]
    n = len(x)
    if n == 0:
        return NullVerdict("inconclusive", None, None, None, None, None, "no value")
    mean = math.fsum(x) / n
    if n < 2:
        why = f"one starting place ({mean:+.2f} {unit}): no standard error, no test possible"
        return NullVerdict("inconclusive", mean, None, None, None, None, why)
    sd = math.sqrt(math.fsum((v - mean) ** 2 for v in x) / (n - 1))
    sem = sd / math.sqrt(n)
    half = float(stats.t.ppf(0.5 + LEVEL / 2, n - 1)) * sem
    low, high = mean - half, mean + half
    excluded = max(abs(low), abs(high))
    interval = f"{LEVEL * 100:.0f} % interval {low:+.2f} to {high:+.2f} {unit} from {n} places"
    if -tol <= low and high <= tol:
        verdict = "agrees"
        reason = f"no advance beyond ±{tol:g} {unit}: the {interval} lies within the tolerance"
    elif low > tol or high < -tol:
        verdict = "differs"
        reason = f"a drift beyond ±{tol:g} {unit}: the {interval} lies outside the tolerance"
    else:
        verdict = "inconclusive"
        holds = "consistent with no advance" if low <= 0 <= high else "a drift is seen"
        reason = (
            f"{holds}; the {interval} excludes only drifts beyond {excluded:.2f} {unit}, "
            f"more than the ±{tol:g} {unit} tolerance: more starting places would narrow it"
        )
    return NullVerdict(verdict, mean, sem, low, high, excluded, reason)
