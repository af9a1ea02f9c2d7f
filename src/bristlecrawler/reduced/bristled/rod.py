"""A tapered bristle as a two-joint discrete elastic rod (a pseudo-rigid-body model).

The bristle of length L (mm), width b, thickness h(s) = h0 + (h1 - h0) s/L, Young's
modulus E (MPa) is replaced by a chain clamped at the body: a rigid first link to the joint
at s_1, a link to the joint at s_2 and a link to the tip, with rotational springs k_1, k_2
(N mm/rad). The joints and springs are the two-point Gauss quadrature of the compliance
weight 1/EI(s) on [0, L] (Golub-Welsch on its moments):

    int_0^L f(s) / EI(s) ds  ~=  c_1 f(s_1) + c_2 f(s_2),   k_j = 1 / c_j,

exact for cubic f. A tip force's small-deflection compliance, int (L - s)^2 / EI ds, and
a tip moment's, int 1 / EI ds, are cubic moments, so the chain has the tapered beam's exact
small-deflection tip stiffness (3 EI / L^3 for a straight one); with ``shear`` the springs
are softened together by the Timoshenko share int ds / (kappa G A) of the tip's transverse
compliance (the FE core's beam). At large deflections the chain follows the elastica: the
moment at each joint is the exact beam's at that point (see :mod:`.elastica`, which
checks it).

Kinematics in the body frame (x along the body, y up): the rest direction of the bristle
is e_r = (-sin alpha, -cos alpha) (the tip trails), its angle theta_r. With joint angles
phi_1 (the second link from rest) and phi_2 (the third link from the second), the tip is

    rho = l_1 e(theta_r + phi_1) + l_2 e(theta_r + phi_1 + phi_2)

from the first joint, and the bristle's energy E = (k_1 phi_1^2 + k_2 phi_2^2) / 2 (mJ).
Given the tip, the chain's two configurations (elbow either way) follow in closed form;
the bristle takes the one of least energy. Units: mm, N, MPa, mJ.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

_KAPPA = 5.0 / 6.0


@dataclass(frozen=True)
class TaperedBristle:
    """A linearly tapered rectangular bristle (the defaults are the paper's, those of
    :class:`bristlecrawler.crawler.parts.Bristle`: this layer cannot import it, and a test
    keeps the two equal).

    Attributes:
        length: L, mm. width: b, mm. thickness_clamp, thickness_tip: h0, h1, mm.
        youngs_modulus: E, MPa. poisson_ratio: nu, -. alpha_deg: inclination from the
        vertical, degrees (the tip trails: sliding along the grain is towards +x).
        shear: include the Timoshenko shear compliance (as the FE core's beam does).
    """

    length: float = 5.0
    width: float = 30.0
    thickness_clamp: float = 3.0
    thickness_tip: float = 0.5
    youngs_modulus: float = 1.1
    poisson_ratio: float = 0.45
    alpha_deg: float = 45.0
    shear: bool = True

    def thickness(self, s):
        """h(s), mm, at arc length s (mm) from the clamp."""
        h0, h1 = self.thickness_clamp, self.thickness_tip
        return h0 + (h1 - h0) * np.asarray(s, dtype=float) / self.length

    def bending_stiffness(self, s):
        """EI(s), N mm^2."""
        return self.youngs_modulus * self.width * self.thickness(s) ** 3 / 12.0

    def shear_stiffness(self, s):
        """kappa G A(s), N."""
        g = self.youngs_modulus / (2.0 * (1.0 + self.poisson_ratio))
        return _KAPPA * g * self.width * self.thickness(s)

    @property
    def tip_radius(self) -> float:
        """Half the tip's thickness: the radius of the disc that touches the substrate, mm."""
        return 0.5 * self.thickness_tip


def _gauss_legendre(n: int, a: float, b: float) -> tuple[np.ndarray, np.ndarray]:
    x, w = np.polynomial.legendre.leggauss(n)
    return 0.5 * (b - a) * (x + 1.0) + a, 0.5 * (b - a) * w


def compliance_moment(bristle: TaperedBristle, m: int) -> float:
    """int_0^L (L - s)^m / EI(s) ds (mm^m / (N mm^2) * mm): the tip's small-deflection
    compliance to a force (m = 2), to a moment (m = 0) and their coupling (m = 1)."""
    s, w = _gauss_legendre(64, 0.0, bristle.length)
    return float(np.sum(w * (bristle.length - s) ** m / bristle.bending_stiffness(s)))


def shear_compliance(bristle: TaperedBristle) -> float:
    """int_0^L ds / (kappa G A(s)), mm/N: the tip's transverse shear compliance."""
    s, w = _gauss_legendre(64, 0.0, bristle.length)
    return float(np.sum(w / bristle.shear_stiffness(s)))


def _two_point_gauss(bristle: TaperedBristle) -> tuple[np.ndarray, np.ndarray]:
    """Nodes s_j (mm) and weights c_j (1/(N mm)) of the 2-point Gauss rule for the weight
    1/EI(s) on [0, L] (the roots of its second orthogonal polynomial)."""
    L = bristle.length
    mu = [compliance_moment(bristle, m) for m in range(4)]  # moments of t = L - s
    # Orthogonal p(t) = t^2 + a t + b: int p t^k w = 0 for k = 0, 1.
    a, b = np.linalg.solve(np.array([[mu[1], mu[0]], [mu[2], mu[1]]]), -np.array(mu[2:4]))
    t = np.sort(np.roots([1.0, a, b]).real)
    c = np.linalg.solve(np.vstack([np.ones(2), t]), np.array(mu[:2]))
    return np.sort(L - t), c[np.argsort(L - t)]


@dataclass(frozen=True)
class Chain:
    """The calibrated two-joint rod of one bristle geometry.

    Attributes:
        s1, s2: joint positions from the clamp, mm. l1, l2: the two elastic links, mm.
        k1, k2: rotational springs, N mm/rad. theta_r: rest angle of the bristle in the
        body frame, rad. radius: tip disc radius, mm.
    """

    s1: float
    s2: float
    l1: float
    l2: float
    k1: float
    k2: float
    theta_r: float
    radius: float

    @classmethod
    def of(cls, bristle: TaperedBristle) -> Chain:
        """Calibrate the chain of ``bristle`` (closed form; cheap, no FE)."""
        s, c = _two_point_gauss(bristle)
        if bristle.shear:
            scale = 1.0 + shear_compliance(bristle) / compliance_moment(bristle, 2)
            c = c * scale
        a = math.radians(bristle.alpha_deg)
        return cls(
            s1=float(s[0]),
            s2=float(s[1]),
            l1=float(s[1] - s[0]),
            l2=float(bristle.length - s[1]),
            k1=float(1.0 / c[0]),
            k2=float(1.0 / c[1]),
            theta_r=math.atan2(-math.cos(a), -math.sin(a)),
            radius=bristle.tip_radius,
        )

    def rest_tip(self) -> np.ndarray:
        """Unloaded tip from the clamp, body frame, mm."""
        L = self.s2 + self.l2
        return L * np.array([math.cos(self.theta_r), math.sin(self.theta_r)])


def chain_fields(chains) -> dict[str, np.ndarray]:
    """The chains' parameters as arrays (one entry per chain, any shape of ``chains``)."""
    arr = np.asarray(chains, dtype=object)
    names = ("s1", "l1", "l2", "k1", "k2", "theta_r", "radius")
    return {n: np.vectorize(lambda c, n=n: getattr(c, n), otypes=[float])(arr) for n in names}


def _wrap(a):
    return (a + np.pi) % (2.0 * np.pi) - np.pi


def joint_angles(rho, p):
    """Both configurations' joint angles for tips ``rho`` (..., 2) from the first joint
    (body frame, mm); ``p`` the :func:`chain_fields` arrays broadcasting with rho[..., 0].
    Returns (phi1, phi2) of shape (2, ...): index 0 elbow one way, 1 the other; a tip out of
    reach is placed on the reach circle (the chain straight)."""
    l1, l2 = p["l1"], p["l2"]
    d2 = rho[..., 0] ** 2 + rho[..., 1] ** 2
    c2 = np.clip((d2 - l1**2 - l2**2) / (2.0 * l1 * l2), -1.0, 1.0)
    q2 = np.arccos(c2)
    phi2 = np.stack([q2, -q2])
    beta = np.arctan2(rho[..., 1], rho[..., 0])
    gamma = np.arctan2(l2 * np.sin(phi2), l1 + l2 * np.cos(phi2))
    phi1 = _wrap(beta - gamma - p["theta_r"])
    return phi1, phi2


def bristle_energy_and_force(rho, p):
    """The bristle's energy E (mJ) and dE/drho (N, body frame) for tips ``rho``
    (..., 2) from the first joint, in its least-energy configuration.

    dE/drho = J^-T (k_1 phi_1, k_2 phi_2), J the chain's Jacobian; it is the force the
    substrate exerts on the tip (in the body frame) when the tip is in equilibrium."""
    phi1, phi2 = joint_angles(rho, p)
    e = 0.5 * (p["k1"] * phi1**2 + p["k2"] * phi2**2)
    pick = np.argmin(e, axis=0)
    take = lambda a: np.take_along_axis(a, pick[None], 0)[0]  # noqa: E731
    phi1, phi2, e = take(phi1), take(phi2), take(e)
    t1 = p["theta_r"] + phi1
    t2 = t1 + phi2
    l1, l2 = p["l1"], p["l2"]
    # Columns of J: d rho / d phi1 = l1 e_perp(t1) + l2 e_perp(t2); d rho / d phi2 = l2 e_perp(t2).
    j11 = -l1 * np.sin(t1) - l2 * np.sin(t2)
    j21 = l1 * np.cos(t1) + l2 * np.cos(t2)
    j12 = -l2 * np.sin(t2)
    j22 = l2 * np.cos(t2)
    det = j11 * j22 - j12 * j21
    det = np.where(np.abs(det) < 1e-12, 1e-12, det)
    m1, m2 = p["k1"] * phi1, p["k2"] * phi2
    # Solve J^T f = m.
    fx = (j22 * m1 - j21 * m2) / det
    fy = (-j12 * m1 + j11 * m2) / det
    return e, np.stack([fx, fy], axis=-1)


def chain_tip(phi1, phi2, p):
    """Tip from the first joint (..., 2) for joint angles (forward kinematics), mm."""
    t1 = p["theta_r"] + phi1
    t2 = t1 + phi2
    return np.stack(
        [p["l1"] * np.cos(t1) + p["l2"] * np.cos(t2), p["l1"] * np.sin(t1) + p["l2"] * np.sin(t2)],
        axis=-1,
    )


def chain_tip_under_force(force, p, iterations: int = 60):
    """Tip from the first joint (mm) of the chain loaded by a tip ``force`` (..., 2) N,
    body frame (see :func:`chain_angles_under_force`)."""
    phi = chain_angles_under_force(force, p, iterations)
    return chain_tip(phi[0], phi[1], p)


def chain_angles_under_force(force, p, iterations: int = 60):
    """Joint angles (2, ...) of the chain loaded by a tip ``force`` (..., 2) N, body
    frame: the equilibrium k_j phi_j = moment of the force about joint j, by Newton from
    the rest shape (dead load; the branch continuous from rest)."""
    phi = np.zeros((2, *np.shape(force)[:-1]))
    fx, fy = force[..., 0], force[..., 1]
    for _ in range(iterations):
        t1 = p["theta_r"] + phi[0]
        t2 = t1 + phi[1]
        a1 = (
            p["l1"] * np.cos(t1) + p["l2"] * np.cos(t2),
            p["l1"] * np.sin(t1) + p["l2"] * np.sin(t2),
        )
        a2 = (p["l2"] * np.cos(t2), p["l2"] * np.sin(t2))
        m1 = a1[0] * fy - a1[1] * fx
        m2 = a2[0] * fy - a2[1] * fx
        r = np.stack([p["k1"] * phi[0] - m1, p["k2"] * phi[1] - m2])
        # dm1/dphi1 = -(a1 . f), dm1/dphi2 = -(a2 . f) = dm2/dphi1 = dm2/dphi2
        d1 = a1[0] * fx + a1[1] * fy
        d2 = a2[0] * fx + a2[1] * fy
        h11, h12, h22 = p["k1"] + d1, d2, p["k2"] + d2
        det = h11 * h22 - h12 * h12
        step = np.stack([(h22 * r[0] - h12 * r[1]) / det, (h11 * r[1] - h12 * r[0]) / det])
        phi = phi - step
        if np.max(np.abs(step)) < 1e-14:
            break
    return phi
