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


def _pair(x, y):
    """(..., 2) from two arrays of the same shape (np.stack's checks cost more than this
    at the batch sizes here)."""
    out = np.empty((*np.shape(x), 2))
    out[..., 0], out[..., 1] = x, y
    return out


def _arm_parts(bodies: Bodies, q, phi, s):
    """The arms of :func:`_arms` as components: v, g1, g2 each as (x, y) arrays (D, B),
    and d (D, B). v is rotated by theta from the body frame, as g1 and g2 are."""
    c = bodies.chain
    d = node_places(bodies, s)
    p1 = c["theta_r"] + phi[..., 0]
    p2 = p1 + phi[..., 1]
    e2x, e2y = c["l2"] * np.cos(p2), c["l2"] * np.sin(p2)
    e1x, e1y = c["l1"] * np.cos(p1) + e2x, c["l1"] * np.sin(p1) + e2y
    ax = d + c["s1"] * np.cos(c["theta_r"]) + e1x
    ay = -bodies.link[:, None] + c["s1"] * np.sin(c["theta_r"]) + e1y
    ct, st = np.cos(q[:, 2])[:, None], np.sin(q[:, 2])[:, None]
    v = (ct * ax - st * ay, st * ax + ct * ay)
    g1 = (ct * e1x - st * e1y, st * e1x + ct * e1y)
    g2 = (ct * e2x - st * e2y, st * e2x + ct * e2y)
    return v, g1, g2, d


def _arms(bodies: Bodies, q, phi, s):
    """Global vectors: v from the rear body node to each tip, g1 from the first joint and
    g2 from the second joint to the tip (D, B, 2); and the node places d (D, B)."""
    v, g1, g2, d = _arm_parts(bodies, q, phi, s)
    return _pair(*v), _pair(*g1), _pair(*g2), d


def tips_of(bodies: Bodies, q, phi, s):
    """Where the rods put the tips, global, mm (D, B, 2)."""
    (vx, vy), _, _, _ = _arm_parts(bodies, q, phi, s)
    return _pair(q[:, 0:1] + vx, q[:, 1:2] + vy)


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
    ct, st = np.cos(q[:, 2])[:, None], np.sin(q[:, 2])[:, None]
    per_node = (lam[..., 0] * ct + lam[..., 1] * st) + bodies.weight * st
    per_node = np.where(bodies.on, per_node, 0.0)
    return -np.sum(per_node[:, :, None] * bodies.behind, axis=1)


def kkt(bodies: Bodies, q, phi, lam, tips, s, held):
    """Residual (D, n) and Jacobian (D, n, n) of the equilibrium, n = 3 + 4B, unknowns
    ordered (X, Y, theta, then per bristle phi_1, phi_2, lambda_x, lambda_y). A tip not
    ``held`` (D, B) is off the substrate: its rod is at rest and carries nothing."""
    c, on = bodies.chain, bodies.on & held
    D, B = phi.shape[:2]
    (vx, vy), (g1x, g1y), (g2x, g2y), d = _arm_parts(bodies, q, phi, s)
    w = np.where(bodies.on, bodies.weight, 0.0)
    lx = np.where(on, lam[..., 0], 0.0)
    ly = np.where(on, lam[..., 1], 0.0)
    ph1, ph2 = phi[..., 0], phi[..., 1]
    n = 3 + 4 * B
    r = np.zeros((D, n))
    K = np.zeros((D, n, n))
    wd = (w * d).sum(1)
    r[:, 0] = lx.sum(1)
    r[:, 1] = w.sum(1) + ly.sum(1)
    r[:, 2] = wd * np.cos(q[:, 2]) + np.where(on, vx * ly - vy * lx, 0.0).sum(1)
    K[:, 2, 2] = -wd * np.sin(q[:, 2]) + np.where(on, -vy * ly - vx * lx, 0.0).sum(1)
    # Per bristle i, its unknowns at o = 3 + 4 i: phi_1, phi_2, lambda_x, lambda_y.
    o = 3 + 4 * np.arange(B)
    a1 = -g1y * ly - g1x * lx
    a2 = -g2y * ly - g2x * lx
    r[:, o] = np.where(on, c["k1"] * ph1 + (g1x * ly - g1y * lx), ph1)
    r[:, o + 1] = np.where(on, c["k2"] * ph2 + (g2x * ly - g2y * lx), ph2)
    r[:, o + 2] = np.where(on, q[:, 0:1] + vx - tips[..., 0], 0.0)
    r[:, o + 3] = np.where(on, q[:, 1:2] + vy - tips[..., 1], 0.0)
    K[:, o, 2] = K[:, 2, o] = a1
    K[:, o + 1, 2] = K[:, 2, o + 1] = a2
    K[:, o, o] = c["k1"] + a1
    K[:, o, o + 1] = K[:, o + 1, o] = a2
    K[:, o + 1, o + 1] = c["k2"] + a2
    K[:, o, o + 2] = K[:, o + 2, o] = -g1y
    K[:, o, o + 3] = K[:, o + 3, o] = g1x
    K[:, o + 1, o + 2] = K[:, o + 2, o + 1] = -g2y
    K[:, o + 1, o + 3] = K[:, o + 3, o + 1] = g2x
    K[:, o + 2, 0] = K[:, 0, o + 2] = 1.0
    K[:, o + 3, 1] = K[:, 1, o + 3] = 1.0
    K[:, o + 2, 2] = K[:, 2, o + 2] = -vy
    K[:, o + 3, 2] = K[:, 2, o + 3] = vx
    # A free tip's unknowns decouple: its rod at rest, its multiplier zero.
    fixed = ~bodies.free_pitch
    if not on.all() or fixed.any():
        live = np.ones((D, n), bool)
        live[:, 3:] = np.repeat(on, 4, axis=1)
        live[:, 2] = ~fixed
        K = np.where(live[:, :, None] & live[:, None, :], K, 0.0)
        diag = np.arange(n)
        K[:, diag, diag] = np.where(live, K[:, diag, diag], 1.0)
        r[:, 2] = np.where(fixed, 0.0, r[:, 2])
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
    act = np.arange(D)
    sub = (bodies, tips, s, held)
    for _ in range(opts.iterations if D else 0):
        xa = x[act]
        qa, pa, la = split_unknowns(xa, B)
        r, K = kkt(sub[0], qa, pa, la, *sub[1:])
        small = np.abs(r).max(axis=1) < opts.tol
        done[act[small]] = True
        step = newton_steps(K, r)
        ang = np.abs(step[:, 3:].reshape(-1, B, 4)[..., :2]).max(axis=(1, 2))
        scale = np.minimum(1.0, opts.max_angle / np.maximum(ang, 1e-300))
        x[act] = np.where(small[:, None], xa, xa + scale[:, None] * step)
        if small.any():
            # The designs in equilibrium leave the solve; the others go on.
            keep = np.flatnonzero(~small)
            if keep.size == 0:
                break
            act = act[keep]
            sub = (sub[0].take(keep), *(a[keep] for a in sub[1:]))
    q, phi, lam = split_unknowns(x, B)
    return q, phi, lam, done


def newton_steps(K, r):
    """-K^-1 r for each design's system (D, n, n), (D, n). A singular system (one
    design's) must not stop the batch: it gives no step, and that design stays put."""
    try:
        step = -np.linalg.solve(K, r[..., None])[..., 0]
    except np.linalg.LinAlgError:
        ok = np.abs(np.linalg.det(K)) > 1e-300
        K = np.where(ok[:, None, None], K, np.eye(K.shape[1]))
        return -np.linalg.solve(K, np.where(ok[:, None], r, 0.0)[..., None])[..., 0]
    return np.where(np.isfinite(step).all(axis=1)[:, None], step, 0.0)


def split_unknowns(x, B):
    rest = x[:, 3:].reshape(-1, B, 4)
    return x[:, :3], rest[..., :2], rest[..., 2:]
