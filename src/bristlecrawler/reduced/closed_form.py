"""Closed-form gait and energetics of the two-bristle crawler (paper Section 4), all regimes.

Two identical bristles (stiffness k, along-the-grain resistance F_p, any F_n > F_p), stroke
0 -> s~ -> 0 repeated, starting unloaded. With ``c = F_p / k`` (mm) the left spring elongation
``e`` (right one ``-e``) follows a stop operator of ``s/2`` with bounds ``+-c``, hence three
regimes (the paper derives only the third):

1. ``s~ <= 2c``: no tip ever slides; ``Delta = -s/2``, no net motion, no net work.
2. ``2c < s~ <= 4c``: the left tip slides during the first contraction only, then the
   crawler shakes down to elastic cycles:
   ``Delta_net^1 = s~/2 - c``, ``Delta_net^n = 0``, ``W^1 = k (s~^2/4 - c^2)``, ``W^n = 0``.
3. ``s~ > 4c``: paper eqs. (4.9)-(4.16):
   ``Delta_net^1 = s~ - 3c``, ``Delta_net^n = s~ - 4c``,
   ``W^1 = F_p^2/k + 2 F_p (s~ - 3c)``, ``W^n = 2 F_p (s~ - 4c)``.

The formulas meet continuously at the regime boundaries. Every function broadcasts over
NumPy arrays of parameters (design studies evaluate millions of designs at once).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

NO_SLIDING, FIRST_CONTRACTION_ONLY, STEADY_SLIDING = 1, 2, 3


def regime(s_max, fp_over_k):
    """Regime (1, 2 or 3, see module doc) of peak shortening ``s_max`` (mm), ``F_p/k`` (mm)."""
    s, c = np.broadcast_arrays(np.asarray(s_max, float), np.asarray(fp_over_k, float))
    return np.where(
        s <= 2 * c, NO_SLIDING, np.where(s <= 4 * c, FIRST_CONTRACTION_ONLY, STEADY_SLIDING)
    )


def net_advance_first(s_max, fp_over_k):
    """Net advance of the first cycle, Delta_net^1 (mm); paper eq. (4.13) in regime 3."""
    s, c = np.asarray(s_max, float), np.asarray(fp_over_k, float)
    return np.where(s <= 2 * c, 0.0, np.where(s <= 4 * c, 0.5 * s - c, s - 3 * c))


def net_advance_later(s_max, fp_over_k):
    """Net advance of every cycle n >= 2, Delta_net^n (mm); paper eq. (4.15) in regime 3."""
    s, c = np.asarray(s_max, float), np.asarray(fp_over_k, float)
    return np.where(s <= 4 * c, 0.0, s - 4 * c)


def net_advance(s_max, fp_over_k, cycles):
    """Net advance after ``cycles`` (>= 1) full cycles, mm."""
    n = np.asarray(cycles, float)
    return net_advance_first(s_max, fp_over_k) + (n - 1) * net_advance_later(s_max, fp_over_k)


def work_first(s_max, fp, k):
    """Actuator work over the first cycle, W^1 (mJ); paper eq. (4.16) in regime 3."""
    s, fp, k = np.asarray(s_max, float), np.asarray(fp, float), np.asarray(k, float)
    c = fp / k
    return np.where(
        s <= 2 * c,
        0.0,
        np.where(s <= 4 * c, k * (0.25 * s**2 - c**2), fp * c + 2 * fp * (s - 3 * c)),
    )


def work_later(s_max, fp, k):
    """Actuator work over every cycle n >= 2, W^n (mJ); paper eq. (4.17) in regime 3."""
    s, fp, k = np.asarray(s_max, float), np.asarray(fp, float), np.asarray(k, float)
    c = fp / k
    return np.where(s <= 4 * c, 0.0, 2 * fp * (s - 4 * c))


def work(s_max, fp, k, cycles):
    """Actuator work over ``cycles`` (>= 1) full cycles, mJ."""
    n = np.asarray(cycles, float)
    return work_first(s_max, fp, k) + (n - 1) * work_later(s_max, fp, k)


def _elongation_bounds(s_max, fp_over_k):
    """Left-spring elongation (mm) at the top of every contraction and at the end of the
    first cycle: ``e_top = min(s~/2, c)``, ``e_bottom = max(e_top - s~/2, -c)``. Every
    cycle n >= 2 starts from ``e_bottom`` and reaches ``e_top`` again (shakedown)."""
    s, c = np.asarray(s_max, float), np.asarray(fp_over_k, float)
    top = np.minimum(0.5 * s, c)
    return top, np.maximum(top - 0.5 * s, -c)


def _half_cycle_mean_abs(a, s_max, c):
    """Time mean of ``|clip(a + s/2, -c, c)|`` over half a sin^2 stroke (s from 0 to s~).

    With ``s = s~ sin^2(theta)``, theta is uniform in time on [0, pi/2]; the integrand is
    piecewise linear in s with kinks where the clip starts and ends and where it changes
    sign, and ``int sin^2 = theta/2 - sin(2 theta)/4`` integrates each piece exactly.
    """
    s = np.asarray(s_max, float)

    def theta(x):
        return np.arcsin(np.sqrt(np.clip(x / s, 0.0, 1.0)))

    def prim(th):
        return 0.5 * th - 0.25 * np.sin(2.0 * th)

    t1, t0, t2 = theta(-2.0 * (c + a)), theta(-2.0 * a), theta(2.0 * (c - a))
    integral = (
        c * t1
        - a * (t0 - t1)
        - 0.5 * s * (prim(t0) - prim(t1))
        + a * (t2 - t0)
        + 0.5 * s * (prim(t2) - prim(t0))
        + c * (0.5 * np.pi - t2)
    )
    return integral / (0.5 * np.pi)


def mean_abs_force(s_max, fp, k, cycles):
    """Time mean of the actuator force |F_c| = k |e| (N) over ``cycles`` sin^2 strokes.

    Each half stroke (contraction, re-extension) takes half the period; the elongation
    follows the stop operator of the module doc, so the mean is exact (no sampling).
    """
    s, fp, k = np.asarray(s_max, float), np.asarray(fp, float), np.asarray(k, float)
    n = np.asarray(cycles, float)
    c = fp / k
    top, bottom = _elongation_bounds(s, c)
    down = _half_cycle_mean_abs(top - 0.5 * s, s, c)  # every re-extension
    first = 0.5 * (_half_cycle_mean_abs(np.zeros_like(c), s, c) + down)
    later = 0.5 * (_half_cycle_mean_abs(bottom, s, c) + down)
    return k * (first + (n - 1) * later) / n


def peak_force(s_max, fp, k):
    """Largest actuator force |F_c| (N) of the run: k s~/2, capped at F_p by sliding."""
    s, fp, k = np.asarray(s_max, float), np.asarray(fp, float), np.asarray(k, float)
    return np.minimum(0.5 * k * s, fp)


def dissipation(s_max, fp, k, cycles):
    """Friction dissipation over ``cycles`` cycles (mJ): F_p times the tips' slip, with
    the slips of the stop operator (left tip in cycle 1: s~ - 2c, later s~ - 4c; right tip
    s~ - 4c every cycle in regime 3). With :func:`work` and the final elastic energy
    ``k e_bottom^2`` it closes the balance W = E_el + D, an independent check."""
    s, fp, k = np.asarray(s_max, float), np.asarray(fp, float), np.asarray(k, float)
    n = np.asarray(cycles, float)
    c = fp / k
    left_first = np.maximum(s - 2 * c, 0.0)
    later = np.maximum(s - 4 * c, 0.0)
    return fp * (left_first + later + (n - 1) * 2 * later)


def final_elastic_energy(s_max, fp, k):
    """Elastic energy stored in the two springs at the end of every cycle (mJ)."""
    _, bottom = _elongation_bounds(s_max, np.asarray(fp, float) / np.asarray(k, float))
    return np.asarray(k, float) * bottom**2


@dataclass(frozen=True)
class TwoBristleTrajectory:
    """Closed-form state along a stroke history (arrays shaped like the input ``s``).

    ``delta`` (mm): front-end displacement; ``force`` (N, shape (..., 2)): forces on the
    crawler through the left and right bristles; ``state`` (shape (..., 2)): 0 stick, +1
    sliding forwards; ``elastic_energy``, ``dissipation``, ``work`` in mJ (cumulative).
    """

    delta: np.ndarray
    force: np.ndarray
    state: np.ndarray
    elastic_energy: np.ndarray
    dissipation: np.ndarray
    work: np.ndarray


def trajectory(s, cycle, contracting, s_max, fp, k) -> TwoBristleTrajectory:
    """Closed-form Delta(t), forces, stick/slip states and energies, stage by stage.

    Args:
        s: shortening (mm) at the instants of interest, 0 <= s <= s_max.
        cycle: cycle number n >= 1 of each instant.
        contracting: True on the contraction branch (s increasing), False on re-extension.
        s_max: peak shortening s~ (mm); fp: F_p (N); k: stiffness (N/mm).

    Stages follow the paper (a: both stick; b: left slides; c: both stick; d: right slides),
    eqs. (4.8)-(4.14) for n = 1 and (4.14) for n >= 2; regimes 1-2 as in the module doc.
    At a transition instant the state is the one of the stage that ends there.
    """
    s = np.asarray(s, float)
    n = np.asarray(cycle, float)
    up = np.asarray(contracting, bool)
    s, n, up = np.broadcast_arrays(s, n, up)
    S, fp, k = float(s_max), float(fp), float(k)
    c = fp / k
    reg = int(regime(S, c))
    first = n <= 1

    if reg == NO_SLIDING:
        e = 0.5 * s
        delta = -0.5 * s
        left = right = np.zeros_like(s)
        diss = np.zeros_like(s)
    elif reg == FIRST_CONTRACTION_ONLY:
        slide_a = first & up & (s > 2 * c)
        e = np.where(first & up, np.minimum(0.5 * s, c), c - 0.5 * (S - s))
        base = np.where(first & up, 0.0, 0.5 * S - c)
        delta = np.where(first & up, -np.minimum(0.5 * s, c), base - 0.5 * s)
        left = slide_a.astype(float)
        right = np.zeros_like(s)
        diss = fp * np.where(first & up, np.maximum(s - 2 * c, 0.0), S - 2 * c)
    else:
        # Position and dissipation at the start of cycle n (n >= 2): paper eq. (4.14).
        B = np.where(first, 0.0, S - 3 * c + (S - 4 * c) * (n - 2))
        D0 = np.where(first, 0.0, fp * (S - 2 * c) + fp * (S - 4 * c) * (2 * n - 3))
        onset_up = np.where(first, 2 * c, 4 * c)  # shortening at which the left tip slides
        e0 = np.where(first, 0.0, -c)
        left = (up & (s > onset_up)).astype(float)
        right = (~up & (s < S - 4 * c)).astype(float)
        e_up = np.minimum(e0 + 0.5 * s, c)
        e_dn = np.maximum(c - 0.5 * (S - s), -c)
        e = np.where(up, e_up, e_dn)
        slip_left = np.maximum(s - onset_up, 0.0)
        slip_left_full = S - onset_up
        slip_right = np.maximum(S - 4 * c - s, 0.0)
        # Delta = (slip of left tip) + e - s + (start position of the cycle).
        delta = np.where(up, B + (e_up - e0) + slip_left - s, B + (e_dn - e0) + slip_left_full - s)
        diss = D0 + fp * np.where(up, slip_left, slip_left_full + slip_right)
    elastic = k * e**2
    force = np.stack([-k * e, k * e], axis=-1)
    state = np.stack([left, right], axis=-1).astype(np.int8)
    return TwoBristleTrajectory(delta, force, state, elastic, diss, elastic + diss)


def branches(t, period):
    """Cycle number and branch of each instant of a periodic stroke with turning points at
    ``t = period/2`` (mod period): returns (cycle >= 1, contracting). An instant ``t = n T``
    closes cycle n (re-extension), so each sample carries the stage that ends there.
    """
    u = np.asarray(t, float) / float(period)
    n = np.maximum(np.ceil(u - 1e-12), 1.0)
    phase = u - (n - 1)
    return n.astype(int), phase <= 0.5 + 1e-12
