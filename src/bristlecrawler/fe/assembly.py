"""Global fields of a :class:`~model.Model` as pure functions of arrays.

* :func:`expand` maps the reduced unknowns ``q`` to full nodal displacements ``u``
  (n_nodes, 3): prescribed DOFs from their motions, rigid-link slaves from their masters
  (a nonlinear map; eliminating the constraints this way is the null-space form of the
  Lagrange-multiplier method, so constraint forces never appear).
* :func:`internal_energy` sums beam and spring energies (mJ); its gradient is the internal
  force and its Hessian the tangent (JAX autodiff).
* :func:`mass_times` is the constant mass matrix applied to a full vector, element by
  element; :func:`external_force` gives dead loads and consistent gravity M g.

Load factor ``lam`` scales loads, gravity, prescribed motions and link stretches together
(static load stepping); dynamics uses ``lam = 1``.
"""

from __future__ import annotations

import jax
import jax.numpy as jnp

from bristlecrawler.fe.beam import beam_energy, spring_energy
from bristlecrawler.fe.section import element_mass


def expand(q, t, lam, params, topo):
    """Full displacements (n_nodes, 3) [mm, mm, rad] from reduced ``q`` at time ``t`` (s)."""
    ix = topo.arrays()
    u = jnp.zeros((topo.n_nodes, 3), dtype=jnp.float64)
    if topo.n_red:
        u = u.at[ix["red"][:, 0], ix["red"][:, 1]].set(q)
    if topo.presc:
        vals = jnp.stack([m(t) for m in params.presc]) * lam
        u = u.at[ix["presc"][:, 0], ix["presc"][:, 1]].set(vals)
    X = params.X
    for level in topo.link_levels:
        sl = ix["links"][list(level), 0]
        ms = ix["links"][list(level), 1]
        stretch = jnp.stack([params.stretch[i](t) for i in level]) * lam
        d0 = X[sl] - X[ms]
        d = d0 * (1.0 + stretch / jnp.linalg.norm(d0, axis=1))[:, None]
        th = u[ms, 2]
        c, s = jnp.cos(th), jnp.sin(th)
        Rd = jnp.stack([c * d[:, 0] - s * d[:, 1], s * d[:, 0] + c * d[:, 1]], axis=1)
        xy = X[ms] + u[ms, :2] + Rd - X[sl]
        u = u.at[sl].set(jnp.concatenate([xy, th[:, None]], axis=1))
    return u


def internal_energy(u, params, topo):
    """Strain energy of beams and springs (mJ)."""
    ix = topo.arrays()
    X = params.X
    total = jnp.zeros((), jnp.float64)
    if topo.elems:
        e = ix["elems"]
        secs = tuple(params.sec[:, k] for k in range(6))
        energies = jax.vmap(beam_energy)(X[e[:, 0]], X[e[:, 1]], u[e[:, 0]], u[e[:, 1]], secs)
        total = total + jnp.sum(energies)
    if topo.springs:
        s = ix["springs"]
        energies = jax.vmap(spring_energy)(
            X[s[:, 0]], X[s[:, 1]], u[s[:, 0]], u[s[:, 1]], params.spring_k
        )
        total = total + jnp.sum(energies)
    return total


def internal_force(u, params, topo):
    """Gradient of :func:`internal_energy` (n_nodes, 3) [N, N, N mm]."""
    return jax.grad(internal_energy)(u, params, topo)


def internal_and_damping_force(u, v, params, topo, masses=None):
    """Internal force and Rayleigh damping force ``C v = a0 M v + a1 K_T(u) v`` (full, N).

    ``K_T v`` is a JVP of the internal force; a topology built without stiffness damping
    (``topo.stiffness_damping`` False, static) leaves it out of the program: with
    mass-proportional damping (the paper's) it and its second derivatives in the Newton
    tangent are work multiplied by zero. (A ``lax.cond`` on a1 instead was timed no faster
    on the paper crawler's step: the conditional inside the Newton loop costs what it saves.)
    On such a topology a1 is not read here: the time step refuses a1 != 0 (status
    UNSUPPORTED_DAMPING), and callers outside it must not pass one. ``masses``: the
    element masses (:func:`element_masses`) where already computed.
    """
    if not topo.stiffness_damping:
        f_int = internal_force(u, params, topo)
        return f_int, params.damping[0] * mass_times(v, params, topo, masses)
    f_int, Kv = jax.jvp(lambda u: internal_force(u, params, topo), (u,), (v,))
    damp = params.damping[0] * mass_times(v, params, topo, masses) + params.damping[1] * Kv
    return f_int, damp


def element_masses(params, topo):
    """Element mass matrices (n_elems, 6, 6) [tonne, tonne mm, tonne mm^2], constant in
    time: a step computes them once for all its residuals."""
    e = topo.arrays()["elems"]
    X = params.X
    L0 = jnp.linalg.norm(X[e[:, 1]] - X[e[:, 0]], axis=1)
    b, h0, h1 = params.sec[:, 2], params.sec[:, 3], params.sec[:, 4]
    lumped = jnp.broadcast_to(params.lumped, L0.shape)
    return jax.vmap(element_mass)(L0, params.rho, b, h0, h1, lumped)


def mass_times(a, params, topo, masses=None):
    """M a for a full vector ``a`` (n_nodes, 3); M is constant (see :mod:`section`).
    ``masses``: :func:`element_masses` where already computed."""
    out = params.node_mass * a
    if topo.elems:
        e = topo.arrays()["elems"]
        Me = element_masses(params, topo) if masses is None else masses
        ae = jnp.concatenate([a[e[:, 0]], a[e[:, 1]]], axis=1)  # (ne, 6)
        fe = jnp.einsum("eij,ej->ei", Me, ae)
        out = out.at[e[:, 0]].add(fe[:, :3]).at[e[:, 1]].add(fe[:, 3:])
    return out


def kinetic_energy(v, params, topo):
    """1/2 v^T M v (mJ)."""
    return 0.5 * jnp.sum(v * mass_times(v, params, topo))


def external_force(t, lam, params, topo, masses=None):
    """Dead point loads times their amplitudes plus consistent gravity M g (full, N / N mm);
    ``masses``: :func:`element_masses` where already computed."""
    g = jnp.zeros((topo.n_nodes, 3)).at[:, :2].set(params.gravity)
    f = mass_times(g, params, topo, masses)
    if topo.load_nodes:
        amp = jnp.stack([m(t) for m in params.load_amp])
        f = f.at[topo.arrays()["load_nodes"]].add(params.load_vec * amp[:, None])
    return lam * f


def potential_energy(u, t, lam, params, topo):
    """Strain energy minus the work of dead loads and gravity (mJ)."""
    return internal_energy(u, params, topo) - jnp.sum(external_force(t, lam, params, topo) * u)


def terms_residual(u, v, t, history, params, terms, freeze=False):
    """Sum of the extra terms' residual contributions (full, internal-force sign).

    ``freeze`` (bool, traced or not) goes to the terms that declare ``freezes = True``
    (contact: closed points keep their committed stick/slip status, see
    :func:`bristlecrawler.fe.newton.newton`); the others ignore it."""
    out = jnp.zeros_like(u)
    for term, p, h in zip(terms, params.extra, history, strict=True):
        if freeze is not False and term.freezes:
            out = out + term.residual(u, v, t, h, p, freeze=freeze)
        else:
            out = out + term.residual(u, v, t, h, p)
    return out
