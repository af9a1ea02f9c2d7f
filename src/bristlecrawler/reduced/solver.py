"""Exact incremental solver of the quasi-static, rate-independent reduced crawler.

Unknowns at time t: the rigid position X_0 of the (massless) body and the elongations e_i of
the N bristle springs; tip positions are ``x_i = X_0 + a_i(t) - e_i`` where ``a_i(t)`` is the
prescribed distance from bristle 0 to bristle i (the body shape). Force on the crawler from
bristle i is ``F_i = -k_i e_i`` (paper eq. 4.5), global balance ``sum_i F_i = 0`` (eq. 4.3),
and each tip obeys the directional law (eq. 4.1): it may slide forwards only at
``k_i e_i = F_p,i`` and backwards only at ``k_i e_i = -F_n,i``.

Between two samples the body shape is interpolated linearly, so the rate problem has
piecewise-constant solutions; stick/slip changes are located exactly (no regularisation):

* Long stretches with an unchanged stick/slip mode are advanced in closed form and in bulk
  (vectorised over samples): with S the sliding and K the sticking bristles,
  ``dX_0 = -sum_K k_i da_i / sum_K k_i``.
* An interval where the mode changes is integrated event by event: at each sub-step the rate
  problem ``min_{v, xdot} 1/2 sum k_i (v + adot_i - xdot_i)^2`` with sign constraints on the
  tips at yield is solved exactly (its optimality condition is a monotone piecewise-linear
  equation in v), then advanced to the next yield event.

Work is ``W = int sum_i k_i e_i da_i`` (the actuators' power, exact by the trapezoidal rule
because e is piecewise linear), dissipation ``D = sum_i int (F_p xdot+ + F_n xdot-)``; the
balance ``W = E_el + D`` is a genuine check because the three are computed independently.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from bristlecrawler.errors import InputError, SolverError
from bristlecrawler.reduced.model import ReducedModel
from bristlecrawler.states import Slip

# The reduced model's bristle states: the sign of the sliding velocity (Slip.NONE: stick).
SLIP_NONE, SLIP_FORWARD, SLIP_BACKWARD = Slip.NONE, Slip.FORWARD, Slip.BACKWARD


@dataclass(frozen=True)
class Event:
    """A change of the stick/slip state of one bristle at time ``t`` (s)."""

    t: float
    bristle: int
    before: int
    after: int

    @property
    def kind(self) -> str:
        names = {SLIP_NONE: "stick", SLIP_FORWARD: "slip+", SLIP_BACKWARD: "slip-"}
        return f"{names[self.before]}->{names[self.after]}"


@dataclass(frozen=True)
class ReducedResult:
    """Time series of a reduced-model run (all arrays indexed by sample first).

    Attributes:
        t: times, s, shape (M,).
        shortening: segment shortenings, mm, shape (M, N-1).
        X: attachment (body) positions of the bristles, mm, shape (M, N); X[0, 0] = 0.
        x: tip positions, mm, shape (M, N).
        force: force F_i on the crawler through bristle i, N, shape (M, N).
        state: stick/slip state over the interval ending at each sample (0 stick,
            +1 sliding forwards, -1 backwards), shape (M, N).
        elastic_energy, dissipation, work: mJ, shape (M,); dissipation and work cumulative.
        events: every stick/slip change, with its exact time.
        cycle_bounds: sample indices at which cycles start, plus the last sample.
    """

    crawler: ReducedModel
    t: np.ndarray
    shortening: np.ndarray
    X: np.ndarray
    x: np.ndarray
    force: np.ndarray
    state: np.ndarray
    elastic_energy: np.ndarray
    dissipation: np.ndarray
    work: np.ndarray
    events: tuple[Event, ...] = ()
    cycle_bounds: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=int))

    @property
    def delta(self) -> np.ndarray:
        """Displacement of the front end (last bristle attachment), mm: the paper's Delta."""
        return self.X[:, -1] - self.X[0, -1]

    @property
    def rear_displacement(self) -> np.ndarray:
        """Displacement of the rear end (first bristle attachment), mm."""
        return self.X[:, 0] - self.X[0, 0]

    @property
    def net_advance(self) -> float:
        """Front-end displacement at the end of the run, mm."""
        return float(self.delta[-1])

    @property
    def energy_balance_error(self) -> float:
        """max |W - E_el - D| relative to the largest of max|W|, max D, max E_el."""
        scale = max(np.abs(self.work).max(), self.dissipation.max(), self.elastic_energy.max())
        if scale == 0.0:
            return 0.0
        return float(np.abs(self.work - self.elastic_energy - self.dissipation).max() / scale)

    def per_cycle(self) -> tuple[np.ndarray, np.ndarray]:
        """Advance (mm) and actuator work (mJ) of each cycle, from ``cycle_bounds``."""
        b = self.cycle_bounds
        if b.size < 2:
            return np.zeros(0), np.zeros(0)
        return np.diff(self.delta[b]), np.diff(self.work[b])


def _zero_set(f, bps: np.ndarray, ftol: float) -> tuple[float, float]:
    """Zero set [lo, hi] of a non-decreasing piecewise-linear ``f`` with kinks at ``bps``.

    ``f`` maps an array of points to values; beyond the outer kinks it is linear, so one
    extra point on each side gives the end slopes exactly. Raises SolverError if the zero
    set is empty or unbounded (no or no unique force balance).
    """
    pts = np.concatenate([[bps[0] - 1.0], bps, [bps[-1] + 1.0]])
    vals = f(pts)
    slope_l, slope_r = vals[1] - vals[0], vals[-1] - vals[-2]

    def extrapolate(side: str) -> float:
        slope, p, v = (slope_l, pts[0], vals[0]) if side == "l" else (slope_r, pts[-1], vals[-1])
        if slope <= ftol:
            raise SolverError("no unique force balance: every tip at yield pulls the same way")
        return p - v / slope

    def interpolate(a: int, b: int) -> float:
        if vals[b] - vals[a] <= ftol:
            return 0.5 * (pts[a] + pts[b])
        return pts[a] - vals[a] * (pts[b] - pts[a]) / (vals[b] - vals[a])

    up = np.flatnonzero(vals >= -ftol)
    if up.size == 0:
        lo = extrapolate("r")
    elif up[0] == 0:
        lo = extrapolate("l") if vals[0] > ftol else pts[0]
        if vals[0] <= ftol and slope_l <= ftol:
            raise SolverError("no unique force balance: indeterminate towards -infinity")
    else:
        lo = interpolate(up[0] - 1, up[0])
    down = np.flatnonzero(vals <= ftol)
    if down.size == 0:
        hi = extrapolate("l")
    elif down[-1] == pts.size - 1:
        hi = extrapolate("r") if vals[-1] < -ftol else pts[-1]
        if vals[-1] >= -ftol and slope_r <= ftol:
            raise SolverError("no unique force balance: indeterminate towards +infinity")
    else:
        hi = interpolate(down[-1], down[-1] + 1)
    return (lo, hi) if lo <= hi else (0.5 * (lo + hi), 0.5 * (lo + hi))


class Stepper:
    """Holds the crawler constants and the exact per-interval kernels."""

    def __init__(self, crawler: ReducedModel, scale: float):
        self.k = crawler.k
        self.upper = crawler.fp / crawler.k  # forward-yield elongation, mm
        self.lower = -crawler.fn / crawler.k  # backward-yield elongation, mm
        self.fp, self.fn = crawler.fp, crawler.fn
        self.tol = 1e-12 * scale

    def rate(self, e: np.ndarray, da: np.ndarray) -> tuple[float, np.ndarray, np.ndarray]:
        """Exact rate solution for a body-shape rate ``da`` (mm per unit parameter).

        The body rate v solves ``g(v) = sum_i k_i edot_i(v) = 0`` (balance), g monotone
        piecewise linear. When g vanishes on a whole interval (tips at forward and backward
        yield balance exactly, e.g. F_n = F_p) the rate problem is not unique; then the
        slip rates of least ``sum k_i xdot_i^2`` are taken, which keeps mirror-symmetric
        crawlers symmetric. Returns (v, edot, xdot).
        """
        k, tol = self.k, self.tol
        fwd = e >= self.upper - tol
        bwd = e <= self.lower + tol
        if not (fwd | bwd).any():
            v = -float(k @ da) / float(k.sum())
            return v, v + da, np.zeros_like(da)

        def edot_of(v: np.ndarray) -> np.ndarray:
            w = v[:, None] + da
            return np.where(fwd, np.minimum(w, 0.0), np.where(bwd, np.maximum(w, 0.0), w))

        bps = np.unique(-da[fwd | bwd])
        ftol = 1e-13 * float(k.sum()) * max(float(np.abs(da).max()), 1.0)
        lo, hi = _zero_set(lambda v: edot_of(v) @ k, bps, ftol)
        if hi - lo > tol:

            def xdot_of(v: np.ndarray) -> np.ndarray:
                return v[:, None] + da - edot_of(v)

            lo2, hi2 = _zero_set(lambda v: xdot_of(v) @ k, bps, ftol)
            v = float(np.clip(0.5 * (lo2 + hi2), lo, hi))
        else:
            v = 0.5 * (lo + hi)
        edot = edot_of(np.array([v]))[0]
        return v, edot, v + da - edot

    def mode(self, xdot: np.ndarray) -> np.ndarray:
        return np.where(
            xdot > self.tol, SLIP_FORWARD, np.where(xdot < -self.tol, SLIP_BACKWARD, SLIP_NONE)
        )

    def time_to_yield(self, e: np.ndarray, edot: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Parameter increments after which each spring reaches its forward / backward yield
        elongation at rate ``edot`` (inf where it never does)."""
        tol = self.tol
        with np.errstate(divide="ignore", invalid="ignore"):
            up = np.where((edot > 0) & (e < self.upper - tol), (self.upper - e) / edot, np.inf)
            lo = np.where((edot < 0) & (e > self.lower + tol), (self.lower - e) / edot, np.inf)
        return up, lo

    def interval(self, e, x, X0, da, t0, t1, prev_mode, events):
        """Integrate one interval event by event. Returns e, x, X0, mode, dW, dD."""
        remaining, dW, dD, tau0 = 1.0, 0.0, 0.0, 0.0
        k = self.k
        mode = prev_mode
        for _ in range(8 * k.size + 16):
            v, edot, xdot = self.rate(e, da)
            new_mode = self.mode(xdot)
            for i in np.flatnonzero(new_mode != mode):
                events.append(
                    Event(float(t0 + tau0 * (t1 - t0)), int(i), int(mode[i]), int(new_mode[i]))
                )
            mode = new_mode
            up, lo = self.time_to_yield(e, edot)
            hit = np.minimum(up, lo)
            i_hit = int(np.argmin(hit))
            yielded = float(hit[i_hit]) <= remaining
            step = min(float(hit[i_hit]), remaining)
            e_new = e + edot * step
            dW += float(k @ (0.5 * (e + e_new) * da)) * step
            dD += float(self.fp @ np.maximum(xdot, 0.0) + self.fn @ np.maximum(-xdot, 0.0)) * step
            x = x + xdot * step
            X0 = X0 + v * step
            e = e_new
            remaining -= step
            tau0 += step
            if yielded:  # put the tip that reached yield exactly on its bound
                e[i_hit] = self.upper[i_hit] if up[i_hit] <= lo[i_hit] else self.lower[i_hit]
            if remaining <= 1e-15:
                return e, x, X0, mode, dW, dD
        raise SolverError(
            f"stick/slip events did not settle within the interval t=[{t0:g}, {t1:g}] s"
        )


def solve(
    crawler: ReducedModel,
    t: np.ndarray,
    shortening: np.ndarray,
    cycle_bounds: np.ndarray | None = None,
) -> ReducedResult:
    """Solve the quasi-static evolution for sampled segment shortenings.

    Args:
        crawler: the reduced crawler (N bristles).
        t: sample times, s, strictly increasing, shape (M,).
        shortening: segment shortenings at those times, mm, shape (M, N-1) (or (M,) when
            N = 2). The crawler starts unloaded (all springs at rest) at ``t[0]``.
        cycle_bounds: optional sample indices where cycles start (for per-cycle metrics).

    Returns:
        ReducedResult. Raises InputError on inconsistent input, SolverError if the rate
        problem has no solution (cannot happen for valid crawlers).
    """
    t, s = checked_samples(crawler, t, shortening)
    n = crawler.n_bristles
    a = np.zeros((t.size, n))
    a[:, 1:] = np.cumsum(crawler.segment_lengths - s, axis=1)
    M = t.size
    scale = crawler.length + float(np.max(crawler.fn / crawler.k))
    st = Stepper(crawler, scale)
    k = crawler.k

    X0 = np.zeros(M)
    e = np.zeros((M, n))
    x = np.zeros((M, n))
    x[0] = a[0]
    mode_out = np.zeros((M, n), dtype=np.int8)
    W = np.zeros(M)
    D = np.zeros(M)
    events: list[Event] = []
    mode = np.zeros(n, dtype=np.int8)

    m, chunk = 0, 64
    while m < M - 1:
        da0 = a[m + 1] - a[m]
        _, edot, xdot = st.rate(e[m], da0)
        up, lo = st.time_to_yield(e[m], edot)
        if min(up.min(), lo.min()) < 1.0:
            em, xm, X0m, mode, dW, dD = st.interval(
                e[m].copy(), x[m].copy(), X0[m], da0, t[m], t[m + 1], mode, events
            )
            e[m + 1], x[m + 1], X0[m + 1] = em, xm, X0m
            W[m + 1], D[m + 1] = W[m] + dW, D[m] + dD
            mode_out[m + 1] = mode
            m += 1
            chunk = 64
            continue
        new_mode = st.mode(xdot)
        for i in np.flatnonzero(new_mode != mode):
            events.append(Event(float(t[m]), int(i), int(mode[i]), int(new_mode[i])))
        mode = new_mode

        q, clean = _bulk(st, crawler, a, (e, x, X0, W, D, mode_out), mode, m, min(M - 1, m + chunk))
        chunk = chunk * 2 if clean else 64
        m += q

    X = X0[:, None] + a
    bounds = np.asarray(cycle_bounds if cycle_bounds is not None else [0, M - 1], dtype=int)
    return ReducedResult(
        crawler=crawler,
        t=t,
        shortening=s,
        X=X,
        x=x,
        force=-k * e,
        state=mode_out,
        elastic_energy=0.5 * (e**2) @ k,
        dissipation=D,
        work=W,
        events=tuple(events),
        cycle_bounds=bounds,
    )


def checked_samples(crawler: ReducedModel, t, shortening) -> tuple[np.ndarray, np.ndarray]:
    """Sample times (M,) and shortenings (M, N - 1) as float arrays; InputError naming
    what is wrong with them (shape, non-finite values, times not increasing, a stroke the
    crawler cannot take)."""
    t = np.asarray(t, dtype=float)
    s = np.asarray(shortening, dtype=float)
    if s.ndim == 1:
        s = s[:, None]
    n = crawler.n_bristles
    if t.ndim != 1 or t.size < 2 or s.shape != (t.size, n - 1):
        raise InputError(f"shortening must have shape ({t.size}, {n - 1}), got {s.shape}")
    if not (np.all(np.isfinite(t)) and np.all(np.isfinite(s))):
        raise InputError("times and shortenings must be finite")
    if np.any(np.diff(t) <= 0):
        raise InputError("sample times must be strictly increasing")
    crawler.check_stroke(s.max(axis=0))
    return t, s


def _bulk(st, crawler, a, out, mode, m: int, end: int) -> tuple[int, bool]:
    """Advance the unchanged ``mode`` over samples ``m`` .. ``end`` at once, writing the
    accepted samples into ``out`` = (e, x, X0, W, D, mode_out); returns the intervals
    accepted (up to the first one where a sticking spring leaves its band or a slipping
    tip turns) and whether all were."""
    e, x, X0, W, D, mode_out = out
    k, tol = crawler.k, st.tol
    stick = mode == SLIP_NONE
    da = a[m : end + 1] - a[m]
    # Body motion: balance of the sticking springs; with every tip sliding (a degenerate
    # balance, F_n = F_p) the least-squares slip rates of the rate problem.
    w = stick if stick.any() else np.ones_like(stick)
    dX0 = -(da[:, w] @ k[w]) / k[w].sum()
    disp = dX0[:, None] + da
    e_try = np.where(stick, e[m] + disp, e[m])
    x_try = np.where(stick, x[m], x[m] + disp)
    bad_e = ((e_try > st.upper + tol) | (e_try < st.lower - tol)) & stick
    dx = np.diff(x_try, axis=0)
    bad_x = (mode * dx < -tol) & ~stick
    bad = bad_e[1:].any(axis=1) | bad_x.any(axis=1)
    q = int(np.argmax(bad)) if bad.any() else end - m  # accepted intervals
    sl = slice(m + 1, m + q + 1)
    e[sl], x[sl], X0[sl] = e_try[1 : q + 1], x_try[1 : q + 1], X0[m] + dX0[1 : q + 1]
    mode_out[sl] = mode
    ksum = e_try[: q + 1] * k
    dW = np.einsum("ij,ij->i", 0.5 * (ksum[1:] + ksum[:-1]), np.diff(da[: q + 1], axis=0))
    f = np.where(mode > 0, crawler.fp, crawler.fn)
    dD = np.abs(dx[:q]) @ np.where(stick, 0.0, f)
    W[sl] = W[m] + np.cumsum(dW)
    D[sl] = D[m] + np.cumsum(dD)
    return q, not bad.any()
