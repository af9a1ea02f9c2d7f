"""The body's equilibrium with sliding tips at frozen s: each tip that may slide has its
place on its path among the unknowns, and Coulomb's law in complementarity form as its
equation, so that which tips stick and which slide comes out of the solve.

With the tips ``held`` at arc lengths u_i on their paths c(u), the equilibrium of
:mod:`.body` has unknowns (q, phi, lambda). A tip that may slide is held on its path but
not at a fixed u: its u is one more unknown. With R_t = -lambda . t(u) and
R_n = -lambda . n(u) the substrate's tangential and normal force on it and
du = u - u_0 its slide from where it was, Coulomb's law (stick with |R_t| <= mu R_n, or
slide with R_t = -sign(du) mu R_n) is the one equation (Alart & Curnier, Comput. Methods
Appl. Mech. Eng. 92, 1991)

    R_t = proj_[-mu R_n, mu R_n] (R_t - c du),

c > 0 a scale (N/mm) that changes the iterates, not the solution. It is piecewise
smooth: where |R_t - c du| <= mu R_n it reads c du = 0 (the tip sticks), elsewhere
sigma lambda . t + mu lambda . n = 0 with sigma = sign(c du - R_t) the way the tip slides
(it is on its cone's edge). All of a design's tips are solved together with the body by a
semismooth Newton method: each iteration takes the branch of each tip from the current
iterate and the Jacobian of that branch (dc/du = t, dt/du = kappa n, dn/du = -kappa t,
kappa the path's curvature as its samples are interpolated), with a backtracking line
search on the residual. The stiff coupling of three or more tips through the body is in
the Jacobian, and no active set is guessed. Units: mm, N, mJ, rad.
"""

from __future__ import annotations

import numpy as np

from bristlecrawler.reduced.bristled.body import NewtonOptions, kkt, split_unknowns

#: Alart-Curnier's scale c, N/mm (about a tip's tangential stiffness through its rod).
SCALE = 10.0


def _system(bodies, contacts, x, u0, free, s, held, c=SCALE):
    """Residual (D, n + B) and Jacobian of the equilibrium with the tips' u appended, on
    the branch each tip's Coulomb law takes at ``x``; also returns which tips slide
    (D, B) and their directions (+-1)."""
    D, B = u0.shape
    n0 = 3 + 4 * B
    q, phi, lam = split_unknowns(x[:, :n0], B)
    u = x[:, n0:]
    centre, t, n = contacts.frame(u)
    dc, kappa = contacts.derivatives(u)
    r0, k0 = kkt(bodies, q, phi, lam, centre, s, held)
    r = np.zeros((D, n0 + B))
    K = np.zeros((D, n0 + B, n0 + B))
    r[:, :n0], K[:, :n0, :n0] = r0, k0
    live = bodies.on & held
    mu = contacts.mu[:, None]
    lt = np.sum(lam * t, -1)
    ln = np.sum(lam * n, -1)
    z = -lt - c * (u - u0)
    bound = mu * np.maximum(-ln, 0.0)
    sl = free & live & (np.abs(z) > bound)
    dirn = np.where(z > 0, -1.0, 1.0)
    rows = np.arange(B)
    o = 3 + 4 * rows
    cols = n0 + rows
    K[:, o + 2, cols] = np.where(live, -dc[..., 0], 0.0)
    K[:, o + 3, cols] = np.where(live, -dc[..., 1], 0.0)
    r[:, cols] = np.where(sl, dirn * lt + mu * ln, c * (u - u0))
    grad = dirn[..., None] * t + mu[..., None] * n
    K[:, cols, o + 2] = np.where(sl, grad[..., 0], 0.0)
    K[:, cols, o + 3] = np.where(sl, grad[..., 1], 0.0)
    K[:, cols, cols] = np.where(sl, kappa * (dirn * ln - mu * lt), c)
    return r, K, sl, dirn


def coulomb_equilibrium(
    bodies, contacts, pose, u, s, free, du_cap: float, opts: NewtonOptions, c: float = SCALE
):
    """The equilibrium at ``s`` with the tips ``free`` (D, B) sticking or sliding along
    their paths by Coulomb's law, the other held tips where they are (semismooth Newton;
    no tip moves more than ``du_cap`` mm in one iteration, no joint angle more than
    ``opts.max_angle``). ``pose`` is (q, phi, lambda, held).

    Returns (pose, u, converged (D,)); a design's result holds only where it converged."""
    q, phi, lam, held = pose
    D, B = u.shape
    n0 = 3 + 4 * B
    x = np.concatenate([q, np.concatenate([phi, lam], -1).reshape(D, 4 * B), u], -1)
    u0 = u
    done = np.zeros(D, bool)

    def system(rows, at):
        return _system(
            bodies.take(rows), contacts.take(rows), at, u0[rows], free[rows], s[rows], held[rows], c
        )

    # The system at an accepted trial step is the next iteration's: kept, not assembled twice.
    kept_r = np.zeros((D, n0 + B))
    kept_K = np.zeros((D, n0 + B, n0 + B))
    kept = np.zeros(D, bool)
    for _ in range(opts.iterations):
        act = np.flatnonzero(~done)
        if act.size == 0:
            break
        xa = x[act]
        new = act[~kept[act]]
        if new.size:
            kept_r[new], kept_K[new], _, _ = system(new, x[new])
        r, K = kept_r[act], kept_K[act].copy()
        size = np.abs(r).max(axis=1)
        small = size < opts.tol
        done[act[small]] = True
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
        step = np.where(small[:, None], 0.0, scale[:, None] * step)
        # Backtracking: a tip's branch switches where its force crosses its cone's edge,
        # and a full step across a corner's bend can overshoot.
        alpha = np.ones(len(act))
        accepted = small.copy()
        kept[act] = False
        for _ in range(6):
            wait = np.flatnonzero(~accepted)
            if wait.size == 0:
                break
            rows = act[wait]
            r_t, K_t, _, _ = system(rows, xa[wait] + alpha[wait, None] * step[wait])
            good = np.abs(r_t).max(axis=1) < (1.0 - 1e-4 * alpha[wait]) * size[wait]
            kept_r[rows[good]], kept_K[rows[good]] = r_t[good], K_t[good]
            kept[rows[good]] = True
            accepted[wait[good]] = True
            alpha[wait[~good]] *= 0.5
        x[act] = xa + alpha[:, None] * step
    q, phi, lam = split_unknowns(x[:, :n0], B)
    return (q, phi, lam, held), x[:, n0:], done


def solve_slides(bodies, contacts, pose, u, s, must, sliding, dirn, du_cap, newton):
    """The stops of the tips that may slide (``sliding``, (D, B)), each sticking or
    sliding by Coulomb's law (:func:`coulomb_equilibrium`), the others held. Returns
    (pose, u, accepted (D,)): not accepted where the solve failed or a tip that ``must``
    slide (one beyond its cone, going the way ``dirn`` says) went backwards (its
    resistance falls as it goes: a snap, which the caller runs on)."""
    new_pose, new_u, ok = coulomb_equilibrium(bodies, contacts, pose, u, s, sliding, du_cap, newton)
    back = must & (dirn * (new_u - u) < -1e-12)
    return new_pose, new_u, ok & ~back.any(axis=1)
