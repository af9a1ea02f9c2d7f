"""Reference values computed without the FE code (closed forms, ODE shooting, root finding).

numpy/scipy only. Each function cites the formula it evaluates.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq


def elastica_tip_load(load: float, extensibility: float = 0.0) -> dict[str, float]:
    """Cantilever under a dead tip load perpendicular to its undeformed axis.

    Elastica EI theta'' + P cos(theta) = 0 on s in [0, L], theta(0) = 0, theta'(L) = 0
    (e.g. Bisshopp & Drucker 1945; Mattiasson 1981, Table 1), solved by shooting on
    theta'(0) with an 8th-order Runge-Kutta (rtol 1e-12). ``load`` = P L^2 / (E I).
    Returns u/L (tip shortening), v/L (deflection) and the tip rotation theta (rad).

    ``extensibility`` = EI / (EA L^2) adds the axial strain eps = N / EA = load
    extensibility sin(theta) of an extensible, shear-rigid rod (Reissner 1972): then
    x' = (1 + eps) cos, y' = (1 + eps) sin, EI theta'' = -P (1 + eps) cos(theta)
    (derivatives in the reference arc length).
    """

    def rhs(_s, y):
        th, k, _x, _y = y
        stretch = 1.0 + load * extensibility * math.sin(th)
        return [k, -load * stretch * math.cos(th), stretch * math.cos(th), stretch * math.sin(th)]

    def shoot(k0):
        sol = solve_ivp(
            rhs, (0.0, 1.0), [0.0, k0, 0.0, 0.0], method="DOP853", rtol=1e-12, atol=1e-14
        )
        return sol.y[:, -1]

    # theta'(L) is -load at k0 = 0 and > 0 at k0 = 2 load (the moment arm is < 2 L).
    k0 = brentq(lambda k: shoot(k)[1], 0.0, 2.0 * load, xtol=1e-15, rtol=1e-15)
    th, _, x, y = shoot(k0)
    return {"u_over_L": 1.0 - x, "v_over_L": y, "theta": th}


def tapered_bending_compliance(E, b, h0, h1, L) -> float:
    """Tip deflection per unit tip load (mm/N) of a cantilever of thickness h0 -> h1.

    delta / P = int_0^L (L - x)^2 / (E I(x)) dx with I = b h^3 / 12, h = h0 + c x,
    c = (h1 - h0) / L. Substituting z = h(x), L - x = (h1 - z)/c:
    delta / P = 12 / (E b c^3) [ln z + 2 h1 / z - h1^2 / (2 z^2)]_{h0}^{h1}
              = 12 / (E b c^3) [3/2 + ln(h1/h0) - 2 h1/h0 + h1^2 / (2 h0^2)].
    """
    if h1 == h0:
        return 4.0 * L**3 / (E * b * h0**3)
    c = (h1 - h0) / L
    bracket = 1.5 + math.log(h1 / h0) - 2.0 * h1 / h0 + h1**2 / (2.0 * h0**2)
    return 12.0 / (E * b * c**3) * bracket


def tapered_axial_compliance(E, b, h0, h1, L) -> float:
    """int_0^L dx / (E b h(x)) = L ln(h1/h0) / (E b (h1 - h0)) (mm/N)."""
    if h1 == h0:
        return L / (E * b * h0)
    return L * math.log(h1 / h0) / (E * b * (h1 - h0))


def tapered_shear_compliance(G, b, h0, h1, L, kappa=5.0 / 6.0) -> float:
    """Tip shear deflection per unit tip load (mm/N): int_0^L dx / (kappa G b h(x))
    = L ln(h1/h0) / (kappa G b (h1 - h0)) (Timoshenko; kappa = 5/6 for a rectangle)."""
    return tapered_axial_compliance(kappa * G, b, h0, h1, L)


def inclined_horizontal_stiffness(E, b, h0, h1, L, alpha, nu=None, kappa=5.0 / 6.0) -> float:
    """Horizontal tip stiffness (N/mm) of a tapered bristle at angle ``alpha`` from vertical.

    A horizontal tip load H has components H sin(alpha) along the axis and H cos(alpha)
    across it; the horizontal tip displacement is H (sin^2 f_a + cos^2 f_b) (tip free
    vertically, linear theory). Given Poisson's ratio ``nu``, the transverse compliance
    f_b also has the shear term (G = E / (2 (1 + nu))).
    """
    fa = tapered_axial_compliance(E, b, h0, h1, L)
    fb = tapered_bending_compliance(E, b, h0, h1, L)
    if nu is not None:
        fb += tapered_shear_compliance(E / (2.0 * (1.0 + nu)), b, h0, h1, L, kappa)
    return 1.0 / (math.sin(alpha) ** 2 * fa + math.cos(alpha) ** 2 * fb)


def tip_mass_beta(mass_ratio: float) -> float:
    """Lowest root beta of 1 + cos b cosh b + mu b (cos b sinh b - sin b cosh b) = 0.

    Euler-Bernoulli cantilever with a tip point mass M = mu rho A L (e.g. Blevins, *Formulas
    for natural frequency and mode shape*, Table 8-1); omega = beta^2 sqrt(EI/(rho A L^4)).
    """

    def f(b):
        return (
            1.0
            + math.cos(b) * math.cosh(b)
            + mass_ratio * b * (math.cos(b) * math.sinh(b) - math.sin(b) * math.cosh(b))
        )

    grid = np.linspace(1e-3, 2.0, 2001)
    vals = [f(b) for b in grid]
    i = next(i for i in range(len(grid) - 1) if vals[i] * vals[i + 1] <= 0.0)
    return brentq(f, grid[i], grid[i + 1], xtol=1e-15)


def hht_amplification(alpha: float, beta: float, gamma: float, Omega: float) -> np.ndarray:
    """Amplification matrix of HHT/Newmark for x'' + omega^2 x = 0, Omega = omega dt.

    From the scheme's three equations (Hilber, Hughes & Taylor 1977; Hughes 2000,
    Sec. 9.3): a1 + (1 + alpha) w^2 x1 - alpha w^2 x0 = 0, x1 = x0 + h v0 +
    h^2 ((1/2 - beta) a0 + beta a1), v1 = v0 + h ((1 - gamma) a0 + gamma a1), with w = 1,
    h = Omega, acting on (x, v, a).
    """
    h = Omega
    left = np.array([[1.0 + alpha, 0.0, 1.0], [1.0, 0.0, -beta * h**2], [0.0, 1.0, -gamma * h]])
    right = np.array(
        [[alpha, 0.0, 0.0], [1.0, h, (0.5 - beta) * h**2], [0.0, 1.0, (1.0 - gamma) * h]]
    )
    return np.linalg.solve(left, right)


def principal_roots(eigs) -> tuple[float, float]:
    """(spectral radius, algorithmic damping ratio -ln(rho)/Omega_bar) of the principal pair."""
    eigs = np.asarray(eigs, dtype=complex)
    z = (
        eigs[np.argmax(np.abs(eigs.imag))]
        if np.any(np.abs(eigs.imag) > 1e-12)
        else eigs[np.argmax(np.abs(eigs))]
    )
    rho = float(np.abs(z))
    ang = float(abs(np.angle(z)))
    return rho, (-math.log(rho) / ang if ang > 0 else float("nan"))
