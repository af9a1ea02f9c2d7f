"""The exact large-deflection tapered cantilever (the elastica) under a dead tip force.

The reference that the two-joint rod of :mod:`.rod` is checked against. The
inextensible Euler-Bernoulli beam clamped at s = 0 at angle theta_0, loaded at its tip by a
force F = (F_x, F_y) (N):

    x' = cos theta,  y' = sin theta,  theta' = M / EI(s),
    M' = -(F_y cos theta - F_x sin theta),    M(L) = 0,

(M the bending moment, N mm; ' = d/ds), solved by shooting on M(0) with fourth-order
Runge-Kutta steps and Newton's method. Small deflections of a straight uniform beam give
the tip deflection F L^3 / (3 EI); of a tapered one F int (L - s)^2 / EI ds.
"""

from __future__ import annotations

import math

import numpy as np

from bristlecrawler.reduced.bristled.rod import TaperedBristle


def _rhs(s, z, bristle, fx, fy):
    th, m = z[2], z[3]
    return np.array(
        [
            math.cos(th),
            math.sin(th),
            m / float(bristle.bending_stiffness(s)),
            -(fy * math.cos(th) - fx * math.sin(th)),
        ]
    )


def _shoot(m0, bristle, theta0, fx, fy, steps):
    h = bristle.length / steps
    z = np.array([0.0, 0.0, theta0, m0])
    for i in range(steps):
        s = i * h
        k1 = _rhs(s, z, bristle, fx, fy)
        k2 = _rhs(s + h / 2, z + h / 2 * k1, bristle, fx, fy)
        k3 = _rhs(s + h / 2, z + h / 2 * k2, bristle, fx, fy)
        k4 = _rhs(s + h, z + h * k3, bristle, fx, fy)
        z = z + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
    return z


def elastica_tip(
    bristle: TaperedBristle, force, theta0: float | None = None, steps: int = 400
) -> np.ndarray:
    """The tip's position (x, y) from the clamp (mm) of the tapered Euler-Bernoulli
    cantilever under the dead tip force ``force`` (N), clamped at angle ``theta0`` (rad;
    default the bristle's rest angle, the tip trailing). Load steps from zero keep the
    branch continuous from the unloaded beam."""
    if theta0 is None:
        a = math.radians(bristle.alpha_deg)
        theta0 = math.atan2(-math.cos(a), -math.sin(a))
    fx, fy = (float(v) for v in force)
    m0 = 0.0
    for frac in np.linspace(0.1, 1.0, 10):
        gx, gy = frac * fx, frac * fy
        for _ in range(30):
            r = _shoot(m0, bristle, theta0, gx, gy, steps)[3]
            dm = 1e-6 * max(1.0, abs(m0))
            dr = (_shoot(m0 + dm, bristle, theta0, gx, gy, steps)[3] - r) / dm
            m0 -= r / dr
            if abs(r) < 1e-12:
                break
    z = _shoot(m0, bristle, theta0, fx, fy, steps)
    return z[:2]
