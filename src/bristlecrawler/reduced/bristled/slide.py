"""The body's equilibrium with sliding tips: each sliding tip's place on its path among the
unknowns, Coulomb's law its equation.

With the tips ``held`` at arc lengths u_i on their paths c(u), the equilibrium of
:mod:`.body` has unknowns (q, phi, lambda). A tip that slides is held on its path but not
at a fixed u: its u is one more unknown, and its equation is Coulomb's law on the cone's
edge in the direction it slides (sigma_i = +-1 along the path),

    sigma_i lambda_i . t(u_i) + mu lambda_i . n(u_i) = 0

(-lambda_i is the substrate's force on the tip, so this says |R . t| = mu R . n with the
friction opposing the slide). A tip that sticks keeps u_i = u_i0. All the sliding tips of
a design are solved together with the body, by Newton's method on the whole system with
its exact Jacobian (dc/du = t, dt/du = kappa n, dn/du = -kappa t, kappa the path's
curvature, as the path's samples are interpolated): the stiff coupling of three or more
tips through the body is in the Jacobian, so the tips cannot overshoot one another.
Units: mm, N, mJ, rad.
"""

from __future__ import annotations

import numpy as np

from bristlecrawler.reduced.bristled.body import NewtonOptions, kkt, split_unknowns


def _system(bodies, contacts, x, u, u0, sliding, dirn, s, held):
    """Residual (D, n + B) and Jacobian of the equilibrium with the tips' u appended."""
    D, B = u.shape
    q, phi, lam = split_unknowns(x, B)
    centre, t, n = contacts.frame(u)
    dc, kappa = contacts.derivatives(u)
    r0, k0 = kkt(bodies, q, phi, lam, centre, s, held)
    n0 = r0.shape[1]
    r = np.zeros((D, n0 + B))
    K = np.zeros((D, n0 + B, n0 + B))
    r[:, :n0], K[:, :n0, :n0] = r0, k0
    live = bodies.on & held
    sl = sliding & live
    mu = contacts.mu[:, None]
    lt = np.sum(lam * t, -1)
    ln = np.sum(lam * n, -1)
    rows = np.arange(B)
    o = 3 + 4 * rows
    cols = n0 + rows
    K[:, o + 2, cols] = np.where(live, -dc[..., 0], 0.0)
    K[:, o + 3, cols] = np.where(live, -dc[..., 1], 0.0)
    r[:, cols] = np.where(sl, dirn * lt + mu * ln, u - u0)
    grad = dirn[..., None] * t + mu[..., None] * n
    K[:, cols, o + 2] = np.where(sl, grad[..., 0], 0.0)
    K[:, cols, o + 3] = np.where(sl, grad[..., 1], 0.0)
    K[:, cols, cols] = np.where(sl, kappa * (dirn * ln - mu * lt), 1.0)
    return r, K


def slide_equilibrium(
    bodies, contacts, pose, u, s, sliding, dirn, du_cap: float, opts: NewtonOptions
):
    """The equilibrium at ``s`` with the tips ``sliding`` (D, B) free to move along their
    paths in the directions ``dirn`` (+-1) until their forces are on their cones' edges,
    the other held tips where they are (Newton's method; no tip moves more than
    ``du_cap`` mm in one iteration). ``pose`` is (q, phi, lambda, held).

    Returns (pose, u, converged (D,)); a design's result holds only where it converged
    and every sliding tip went the way it slides (the caller checks the latter)."""
    q, phi, lam, held = pose
    D, B = u.shape
    x = np.concatenate([q, np.concatenate([phi, lam], -1).reshape(D, 4 * B), u], -1)
    u0 = u
    done = np.zeros(D, bool)
    n0 = 3 + 4 * B
    # A Newton step that raises the residual is halved (a tip's cone condition turns
    # sharply where its path bends into a corner, and a full step there can overshoot).
    last = np.full(D, np.inf)
    taken = np.zeros_like(x)
    for _ in range(opts.iterations):
        act = np.flatnonzero(~done)
        if act.size == 0:
            break
        xa = x[act]
        r, K = _system(
            bodies.take(act),
            contacts.take(act),
            xa[:, :n0],
            xa[:, n0:],
            u0[act],
            sliding[act],
            dirn[act],
            s[act],
            held[act],
        )
        size = np.abs(r).max(axis=1)
        small = size < opts.tol
        done[act[small]] = True
        worse = ~small & (size > last[act]) & (np.abs(taken[act]).max(axis=1) > 1e-14)
        ok = np.abs(np.linalg.det(K)) > 1e-300
        K[~ok] = np.eye(K.shape[1])
        step = -np.linalg.solve(K, r[..., None])[..., 0]
        ang = np.abs(step[:, 3:n0].reshape(-1, B, 4)[..., :2]).max(axis=(1, 2))
        slide = np.abs(step[:, n0:]).max(axis=1)
        scale = np.minimum(
            1.0,
            np.minimum(
                opts.max_angle / np.maximum(ang, 1e-300), du_cap / np.maximum(slide, 1e-300)
            ),
        )
        step = scale[:, None] * step
        half = 0.5 * taken[act]
        step = np.where(worse[:, None], -half, np.where(small[:, None], 0.0, step))
        taken[act] = np.where(worse[:, None], half, step)
        last[act] = np.where(worse, last[act], size)
        x[act] = xa + step
    q, phi, lam = split_unknowns(x[:, :n0], B)
    return (q, phi, lam, held), x[:, n0:], done


def solve_slides(bodies, contacts, pose, u, s, must, sliding, dirn, du_cap, newton):
    """The stops of the tips that may slide (``sliding``, (D, B)) found together
    (:func:`slide_equilibrium`), the others sticking; a tip that would slide
    backwards sticks instead and the rest are solved again. Returns (pose, u, accepted
    (D,)): not accepted where the solve failed or a tip that ``must`` slide (one beyond its
    cone) would go backwards (its resistance falls as it goes: a snap, which the caller
    runs on)."""
    accepted = np.zeros(len(u), bool)
    out_pose, out_u = pose, u
    for _ in range(u.shape[1]):
        new_pose, new_u, ok = slide_equilibrium(
            bodies,
            contacts,
            pose,
            u,
            s,
            sliding,
            dirn,
            du_cap,
            newton,
        )
        back = sliding & (dirn * (new_u - u) < -1e-12)
        good = ok & ~back.any(axis=1) & ~accepted
        out_pose = tuple(
            np.where(good.reshape(good.shape + (1,) * (np.ndim(a) - 1)), b, a)
            for a, b in zip(out_pose, new_pose, strict=True)
        )
        out_u = np.where(good[:, None], new_u, out_u)
        accepted |= good
        retry = ok & ~accepted & ~(back & must).any(axis=1)
        if not retry.any():
            break
        sliding = np.where(retry[:, None], sliding & ~back, sliding)
    return out_pose, out_u, accepted
