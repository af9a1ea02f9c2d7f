"""Linearly tapered rectangular section: stiffness and mass of one beam element.

Width ``b`` (mm) is constant, thickness varies linearly from ``h0`` (mm, first node) to
``h1`` (mm, second node); Young's modulus ``E`` (MPa), shear modulus ``G`` (MPa), density
``rho`` (tonne/mm^3), shear correction ``kappa`` = 5/6 (rectangle).

Stiffness comes from the element's *natural* flexibility (force method, e.g. Crisfield,
*Non-linear FE analysis of solids and structures*, Vol. 1, Sec. 7.2; Przemieniecki,
*Theory of matrix structural analysis*, Ch. 5): for the statically determinate element with
end moments M1, M2 (bending moment m(xi) = -M1 (1 - xi) + M2 xi, shear (M1 + M2)/L0) and
axial force N, the complementary energy gives

    f_a = int_0^L0 dx / EA,
    F_b = int_0^L0 [[(1-xi)^2, -xi(1-xi)], [-xi(1-xi), xi^2]] dx / EI
          + shear * int_0^L0 dx / (kappa G A) / L0^2 [[1, 1], [1, 1]],

and the local stiffness is (1/f_a, inv(F_b)). For a uniform section this is the exact
Euler-Bernoulli (shear = 0) or Timoshenko (shear = 1) stiffness EI/(L0 (1+phi)) [[4+phi,
2-phi], [2-phi, 4+phi]]; for a tapered one it is exact up to the quadrature of 1/EI, done
with 8-point Gauss-Legendre per element (elements are short, so EI varies little on each).

Mass uses the same linear interpolation as the nodal translations and rotation, so the
kinetic energy 1/2 int (rho A |dx/dt|^2 + rho I (dtheta/dt)^2) ds is a constant quadratic
form (no gyroscopic terms in the plane): 3-point Gauss integrates it exactly (rho A linear,
rho I cubic, N_i N_j quadratic). The lumped variant is its row sum.
"""

from __future__ import annotations

import jax.numpy as jnp
import numpy as np

_XI8, _W8 = np.polynomial.legendre.leggauss(8)
_XI8, _W8 = 0.5 * (_XI8 + 1.0), 0.5 * _W8
_XI3, _W3 = np.polynomial.legendre.leggauss(3)
_XI3, _W3 = 0.5 * (_XI3 + 1.0), 0.5 * _W3


def _thickness(h0, h1, xi):
    return h0 + (h1 - h0) * xi


def local_stiffness(L0, E, G, b, h0, h1, shear, kappa=5.0 / 6.0):
    """Axial stiffness k_a (N/mm) and 2x2 bending stiffness K_b (N mm) of one element.

    All arguments are scalars; ``shear`` is 0.0 (Euler-Bernoulli) or 1.0 (Timoshenko).
    """
    xi = jnp.asarray(_XI8)
    w = jnp.asarray(_W8)
    h = _thickness(h0, h1, xi)
    EA = E * b * h
    EI = E * b * h**3 / 12.0
    GAs = kappa * G * b * h
    f_a = L0 * jnp.sum(w / EA)
    g11 = L0 * jnp.sum(w * (1.0 - xi) ** 2 / EI)
    g12 = -L0 * jnp.sum(w * xi * (1.0 - xi) / EI)
    g22 = L0 * jnp.sum(w * xi**2 / EI)
    fs = shear * jnp.sum(w / GAs) / L0
    F = jnp.array([[g11 + fs, g12 + fs], [g12 + fs, g22 + fs]])
    det = F[0, 0] * F[1, 1] - F[0, 1] * F[1, 0]
    K_b = jnp.array([[F[1, 1], -F[0, 1]], [-F[1, 0], F[0, 0]]]) / det
    return 1.0 / f_a, K_b


def element_mass(L0, rho, b, h0, h1, lumped):
    """6x6 element mass matrix (tonne; tonne mm^2 on rotations) on (x1, y1, th1, x2, y2, th2).

    ``lumped`` is 0.0 (consistent) or 1.0 (row-sum lumped): a leaf, so both share one program.
    """
    xi = jnp.asarray(_XI3)
    w = jnp.asarray(_W3)
    h = _thickness(h0, h1, xi)
    N = jnp.stack([1.0 - xi, xi])  # (2, q)
    rA = rho * b * h
    rI = rho * b * h**3 / 12.0
    mt = L0 * jnp.einsum("q,iq,jq->ij", w * rA, N, N)
    mr = L0 * jnp.einsum("q,iq,jq->ij", w * rI, N, N)
    mt = (1.0 - lumped) * mt + lumped * jnp.diag(jnp.sum(mt, axis=1))
    mr = (1.0 - lumped) * mr + lumped * jnp.diag(jnp.sum(mr, axis=1))
    # DOF order per node (x, y, theta): interleave the three 2x2 node-coupling blocks.
    blocks = jnp.stack([mt, mt, mr])  # (3, 2, 2): per dof kind, node i x node j
    M = jnp.zeros((6, 6))
    for k in range(3):
        idx = jnp.array([k, 3 + k])
        M = M.at[jnp.ix_(idx, idx)].set(blocks[k])
    return M
