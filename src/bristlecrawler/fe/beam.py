"""Corotational two-node planar beam: energy of one element as a pure function of arrays.

Choice: corotational Euler-Bernoulli/Timoshenko element (Crisfield 1991, Vol. 1, Ch. 7;
Battini & Pacoste 2002). The element's rigid motion is taken out exactly by a frame that
follows the chord; in that frame the strains stay small when the mesh is fine, however
large the rotations (the bristles and the rolled-up cantilever rotate by up to 2 pi), so
the element is exact for large rigid rotations and converges to the elastica. It was
preferred to a geometrically exact (Reissner/Simo) element because (i) the local response
can use the *exact* flexibility of a tapered section (:mod:`section`) with shear as a
switch (Euler-Bernoulli when ``shear = 0``, no shear locking to manage), (ii) its energy is
a closed form of the nodal values, so JAX differentiates it into residual and tangent with
no quadrature of strains, and (iii) it is the standard choice for the B21-like elements of
paper Section 3.

Local deformations (Crisfield eq. 7.4-7.9), with reference chord D = X2 - X1, current
chord d = D + (u2 - u1), chord rotation a = atan2(D x d, D . d):

    u_l      = |d| - |D| = (2 D.du + du.du) / (|d| + |D|)     (no cancellation),
    a        = atan2(D x du, D.D + D.du)                        (no cancellation),
    thbar_i  = wrap(theta_i - a),  i = 1, 2,

and the strain energy is 1/2 k_a u_l^2 + 1/2 thbar^T K_b thbar (N mm = mJ).
"""

from __future__ import annotations

import jax.numpy as jnp

from bristlecrawler.fe.section import local_stiffness


def _wrap(angle):
    """Angle mapped to (-pi, pi]; its derivative is 1, so residuals stay smooth."""
    return jnp.arctan2(jnp.sin(angle), jnp.cos(angle))


def beam_energy(X1, X2, u1, u2, sec):
    """Strain energy (mJ) of one element.

    X1, X2: reference node positions (mm, shape (2,)); u1, u2: nodal (ux mm, uy mm,
    theta rad); ``sec``: tuple (E, G, b, h0, h1, shear) of scalars (MPa, MPa, mm, mm, mm, 1).
    """
    E, G, b, h0, h1, shear = sec
    D = X2 - X1
    du = u2[:2] - u1[:2]
    d = D + du
    L0 = jnp.sqrt(D @ D)
    l = jnp.sqrt(d @ d)
    u_l = (2.0 * D @ du + du @ du) / (l + L0)
    # D x d = D x du exactly. Evaluated as D x (D + du) it cancels: d is rounded to the
    # float64 spacing of |D|, so a is resolved only to ~eps rad whatever the deformation,
    # and on short stiff elements that quantum (nodal force ~ 6 EI eps / L0^2) puts a floor
    # under the residual (|R|/F ~ 5e-10 on the 200-element bench crawler, ~5e-13 this way).
    a = jnp.arctan2(D[0] * du[1] - D[1] * du[0], D @ D + D @ du)
    th = jnp.stack([_wrap(u1[2] - a), _wrap(u2[2] - a)])
    k_a, K_b = local_stiffness(L0, E, G, b, h0, h1, shear)
    return 0.5 * k_a * u_l**2 + 0.5 * th @ K_b @ th


def spring_energy(X1, X2, u1, u2, k):
    """Linear spring of stiffness k (N/mm) between two nodes, rest length |X2 - X1| (mJ)."""
    D = X2 - X1
    du = u2[:2] - u1[:2]
    d = D + du
    L0 = jnp.sqrt(D @ D)
    l = jnp.sqrt(d @ d)
    return 0.5 * k * ((2.0 * D @ du + du @ du) / (l + L0)) ** 2
