"""The rigid body on its elastic bristles: energy, tip forces and the body's equilibrium.

A batch of D designs with up to B bristles each (a design with fewer has its extra
bristles switched off). The body is a rigid bar whose pose is q = (X, Y, theta): its rear
body node at (X, Y), its axis at angle theta. Bristle i hangs from the body node at
d_i(s) along the axis (its rest place less the shortenings of the segments behind it) by a
rigid link of length ``link`` perpendicular to the axis; its two-joint rod (:mod:`.rod`)
reaches from its first joint to its tip at T_i. In the body frame the tip is at

    rho_i = R(-theta) (T_i - (X, Y)) - (d_i, -link) - s_1 e_r,

and the design's potential energy is

    Pi(q, phi) = sum_i (k_1 phi_i1^2 + k_2 phi_i2^2) / 2 + sum_i W_i (Y + d_i sin theta),

W_i the weight on body node i (N; the body's weight shared equally, plus the bristle's
own). With the tips held at T_i, the body and the rods are in equilibrium where the
Lagrangian L = Pi + sum_i lambda_i . (tip_i(q, phi_i) - T_i) is stationary: the unknowns are
the pose, the joint angles and the multipliers lambda_i, and -lambda_i is the force the
substrate exerts on tip i. Near its straight shape a rod's energy as a function of its tip
is not smooth (the joint angles go as the square root of the tip's axial travel), so the
joint angles, not the tips, are the unknowns: in them every equation is smooth, and
Newton's method on the (symmetric) equations converges quadratically.
Units: mm, N, mJ, rad.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Bodies:
    """The designs' bodies and bristles, as arrays over designs (D) and bristles (B).

    Attributes:
        chain: the rods' :func:`~.rod.chain_fields` arrays, each (D, B).
        place: rest place of each body node along the axis from the rear one, mm (D, B).
        behind: segment j lies behind bristle i (D, B, B-1 as 0/1): d_i = place_i -
            sum_j behind_ij s_j.
        on: the bristle exists (D, B) bool.
        link: the rigid links' length, mm (D,).
        weight: weight carried at each body node, N (D, B).
        free_pitch: the body may pitch (D,) bool.
    """

    chain: dict
    place: np.ndarray
    behind: np.ndarray
    on: np.ndarray
    link: np.ndarray
    weight: np.ndarray
    free_pitch: np.ndarray

    def take(self, rows) -> Bodies:
        """The designs ``rows`` (an index array) only."""
        return Bodies(
            {k: v[rows] for k, v in self.chain.items()},
            self.place[rows],
            self.behind[rows],
            self.on[rows],
            self.link[rows],
            self.weight[rows],
            self.free_pitch[rows],
        )


def node_places(bodies: Bodies, s) -> np.ndarray:
    """d_i: where each body node is along the axis with the segments shortened by ``s``
    (D, B-1) mm, (D, B)."""
    # Elementwise sums, not einsum: a design's numbers must not depend on its batch.
    return bodies.place - np.sum(bodies.behind * s[:, None, :], axis=-1)


def _rot(theta, v):
    c, s = np.cos(theta)[:, None], np.sin(theta)[:, None]
    return np.stack([c * v[..., 0] - s * v[..., 1], s * v[..., 0] + c * v[..., 1]], -1)


def _perp(v):
    return np.stack([-v[..., 1], v[..., 0]], -1)


def _cross(a, b):
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


def _arms(bodies: Bodies, q, phi, s):
    """Global vectors: v from the rear body node to each tip, g1 from the first joint and
    g2 from the second joint to the tip (D, B, 2); and the node places d (D, B)."""
    c = bodies.chain
    d = node_places(bodies, s)
    p1 = c["theta_r"] + phi[..., 0]
    p2 = p1 + phi[..., 1]
    e2 = np.stack([c["l2"] * np.cos(p2), c["l2"] * np.sin(p2)], -1)
    e1 = np.stack([c["l1"] * np.cos(p1), c["l1"] * np.sin(p1)], -1) + e2
    a = np.stack(
        [
            d + c["s1"] * np.cos(c["theta_r"]),
            -bodies.link[:, None] + c["s1"] * np.sin(c["theta_r"]),
        ],
        -1,
    )
    th = q[:, 2]
    return _rot(th, a + e1), _rot(th, e1), _rot(th, e2), d


def tips_of(bodies: Bodies, q, phi, s):
    """Where the rods put the tips, global, mm (D, B, 2)."""
    v, _, _, _ = _arms(bodies, q, phi, s)
    return q[:, None, :2] + v


def energy(bodies: Bodies, q, phi, s):
    """The rods' elastic energy and the weight's potential energy, mJ, each (D,)."""
    c, on = bodies.chain, bodies.on
    e = 0.5 * (c["k1"] * phi[..., 0] ** 2 + c["k2"] * phi[..., 1] ** 2)
    height = q[:, 1:2] + node_places(bodies, s) * np.sin(q[:, 2:3])
    e_g = np.sum(np.where(on, bodies.weight * height, 0.0), axis=1)
    return np.sum(np.where(on, e, 0.0), axis=1), e_g


def potential(bodies: Bodies, q, phi, s) -> np.ndarray:
    """Pi = elastic + gravity, mJ (D,)."""
    e_el, e_g = energy(bodies, q, phi, s)
    return e_el + e_g


def actuator_forces(bodies: Bodies, q, lam, s) -> np.ndarray:
    """The force each segment's actuator exerts in equilibrium, f_j = dL/ds_j (N,
    (D, B-1)): the tips' and the weights' pull along the axis on the nodes ahead of it."""
    axis = np.stack([np.cos(q[:, 2]), np.sin(q[:, 2])], -1)[:, None, :]
    per_node = np.sum(lam * axis, -1) + bodies.weight * np.sin(q[:, 2:3])
    per_node = np.where(bodies.on, per_node, 0.0)
    return -np.sum(per_node[:, :, None] * bodies.behind, axis=1)


def kkt(bodies: Bodies, q, phi, lam, tips, s, held):
    """Residual (D, n) and Jacobian (D, n, n) of the equilibrium, n = 3 + 4B, unknowns
    ordered (X, Y, theta, then per bristle phi_1, phi_2, lambda_x, lambda_y). A tip not
    ``held`` (D, B) is off the substrate: its rod is at rest and carries nothing."""
    c, on = bodies.chain, bodies.on & held
    D, B = phi.shape[:2]
    v, g1, g2, d = _arms(bodies, q, phi, s)
    w = np.where(bodies.on, bodies.weight, 0.0)
    lam = np.where(on[..., None], lam, 0.0)
    n = 3 + 4 * B
    r = np.zeros((D, n))
    K = np.zeros((D, n, n))
    ct = np.cos(q[:, 2])
    r[:, 0] = lam[..., 0].sum(1)
    r[:, 1] = w.sum(1) + lam[..., 1].sum(1)
    r[:, 2] = (w * d).sum(1) * ct + np.where(on, _cross(v, lam), 0.0).sum(1)
    K[:, 2, 2] = -(w * d).sum(1) * np.sin(q[:, 2]) + np.where(on, _cross(_perp(v), lam), 0.0).sum(1)
    for i in range(B):
        o = 3 + 4 * i
        f, p, ph, lm = on[:, i], (slice(None), i), phi[:, i], lam[:, i]
        a1, a2 = _cross(_perp(g1[p]), lm), _cross(_perp(g2[p]), lm)
        r[:, o] = np.where(f, c["k1"][p] * ph[:, 0] + _cross(g1[p], lm), ph[:, 0])
        r[:, o + 1] = np.where(f, c["k2"][p] * ph[:, 1] + _cross(g2[p], lm), ph[:, 1])
        r[:, o + 2 : o + 4] = np.where(f[:, None], q[:, :2] + v[p] - tips[p], lam[:, i])
        rows = {
            o: (a1, c["k1"][p] + a1, a2, -g1[p][:, 1], g1[p][:, 0]),
            o + 1: (a2, a2, c["k2"][p] + a2, -g2[p][:, 1], g2[p][:, 0]),
        }
        for row, (dt, d1, d2, lx, ly) in rows.items():
            K[:, row, 2], K[:, 2, row] = dt, dt
            K[:, row, o], K[:, row, o + 1] = d1, d2
            K[:, row, o + 2], K[:, row, o + 3] = lx, ly
            K[:, o + 2, row], K[:, o + 3, row] = lx, ly
        pv = _perp(v[p])
        K[:, o + 2, 0], K[:, 0, o + 2] = 1.0, 1.0
        K[:, o + 3, 1], K[:, 1, o + 3] = 1.0, 1.0
        K[:, o + 2, 2], K[:, 2, o + 2] = pv[:, 0], pv[:, 0]
        K[:, o + 3, 2], K[:, 2, o + 3] = pv[:, 1], pv[:, 1]
        off = ~f
        K[off, o : o + 4, :] = 0.0
        K[off, :, o : o + 4] = 0.0
        K[off, o : o + 4, o : o + 4] = np.eye(4)
    fixed = ~bodies.free_pitch
    r[fixed, 2] = 0.0
    K[fixed, 2, :] = 0.0
    K[fixed, :, 2] = 0.0
    K[fixed, 2, 2] = 1.0
    return r, K


@dataclass(frozen=True)
class NewtonOptions:
    """The equilibrium solve.

    Attributes:
        tol: largest residual at which the body is in equilibrium (N, N mm, mm).
        iterations: Newton iterations at most.
        max_angle: largest change of a joint angle in one iteration, rad (larger steps
            are scaled down).
    """

    tol: float = 1e-10
    iterations: int = 40
    max_angle: float = 0.2


def equilibrium(bodies: Bodies, q, phi, lam, tips, s, held, opts: NewtonOptions = NewtonOptions()):
    """The pose, joint angles and tip multipliers in equilibrium with the tips ``held``
    (D, B) at ``tips``, the others free (Newton's method from (q, phi, lam)). Returns
    (q, phi, lam, converged)."""
    D, B = phi.shape[:2]
    x = np.concatenate([q, np.concatenate([phi, lam], -1).reshape(D, 4 * B)], -1)
    done = np.zeros(D, bool)
    for _ in range(opts.iterations):
        act = np.flatnonzero(~done)
        if act.size == 0:
            break
        xa = x[act]
        qa, pa, la = split_unknowns(xa, B)
        r, K = kkt(bodies.take(act), qa, pa, la, tips[act], s[act], held[act])
        small = np.abs(r).max(axis=1) < opts.tol
        done[act[small]] = True
        # A singular system (one design's) must not stop the batch: that design stays put.
        ok = np.abs(np.linalg.det(K)) > 1e-300
        K[~ok] = np.eye(K.shape[1])
        step = -np.linalg.solve(K, np.where(ok[:, None], r, 0.0)[..., None])[..., 0]
        ang = np.abs(step[:, 3:].reshape(-1, B, 4)[..., :2]).max(axis=(1, 2))
        scale = np.minimum(1.0, opts.max_angle / np.maximum(ang, 1e-300))
        x[act] = np.where(small[:, None], xa, xa + scale[:, None] * step)
    q, phi, lam = split_unknowns(x, B)
    return q, phi, lam, done


def split_unknowns(x, B):
    rest = x[:, 3:].reshape(-1, B, 4)
    return x[:, :3], rest[..., :2], rest[..., 2:]
