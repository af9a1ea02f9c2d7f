"""Node-to-rigid-substrate frictional contact as an extra residual term of the FE solvers.

Plugs :func:`bristlecrawler.contact.node.node_force` into the term protocol of
:mod:`bristlecrawler.fe.terms`: the residual adds, at every contact node, the contact
contribution to the internal force (penalty normal force, Coulomb friction with a stick
anchor as history); the tangent comes from autodiff through the return mapping, so it is
the consistent, non-symmetric one. The history is committed only after a converged step
(never inside Newton), and it accumulates the exact frictional dissipation
``sum F(p_N) |Delta anchor|`` (Coulomb: ``mu p_N``).
"""

from __future__ import annotations

import dataclasses
import functools
from typing import Any

import jax
import jax.numpy as jnp
import numpy as np
from jax.custom_derivatives import SymbolicZero

from bristlecrawler._pytree import pytree
from bristlecrawler.contact.coulomb import FrictionLaw, frozen_status
from bristlecrawler.contact.node import node_force, node_step
from bristlecrawler.contact.profile import project
from bristlecrawler.errors import InputError
from bristlecrawler.fe.terms import Term


def _is_zero(t) -> bool:
    return all(
        isinstance(z, SymbolicZero)
        for z in jax.tree.leaves(t, is_leaf=lambda z: isinstance(z, SymbolicZero))
    )


@jax.custom_jvp
def point_force(x, anchor, substrate, law, radius, mode=None):
    """:func:`~bristlecrawler.contact.node.node_force` of one point (lambda_n = 0), N (2,),
    with a JVP that applies the 2 x 2 tangent ``K = d f / d x``.

    Same values and derivatives as ``node_force``; the point of the rule is cost: the
    FE Newton linearises the residual once and pushes ``3 bs`` seed vectors through the
    linear map (:func:`bristlecrawler.fe.banded.extract`). Autodiff through ``node_force``
    would push each seed through the second derivatives of the projection; with this
    rule ``K`` is computed once from the primal point and each seed costs a 2 x 2 product.
    ``mode``: a frozen status (:func:`~bristlecrawler.contact.coulomb.return_map`), None
    for the return mapping's own.
    """
    return node_force(x, anchor, substrate, law, 0.0, radius, mode)


@functools.partial(point_force.defjvp, symbolic_zeros=True)
def _point_force_jvp(primals, tangents):
    x, anchor, substrate, law, radius, mode = primals
    dx, *others = tangents[:5]  # mode is an integer: no tangent

    def force(x):
        f = node_force(x, anchor, substrate, law, 0.0, radius, mode)
        return f, f

    if _is_zero(dx):
        f = point_force(x, anchor, substrate, law, radius, mode)
        df = jnp.zeros_like(f)
    else:
        # The force comes with K from the same evaluation (one projection, not two).
        K, f = jax.jacfwd(force, has_aux=True)(x)
        df = K @ dx
    if not _is_zero(others):
        # derivatives w.r.t. the parameters (design sensitivities): plain autodiff
        rest = tuple(
            jax.tree.map(
                lambda p, t: jnp.zeros_like(p) if isinstance(t, SymbolicZero) else t,
                prim,
                tan,
                is_leaf=lambda z: isinstance(z, SymbolicZero),
            )
            for prim, tan in zip(primals[1:5], others, strict=True)
        )

        def nf(a, s, w, r):
            return node_force(x, a, s, w, 0.0, r, mode)

        df = df + jax.jvp(nf, primals[1:5], rest)[1]
    return f, df


def attached_points(X, un, offset):
    """Current positions (mm, (..., 2)) of points at reference ``offset`` (..., 2) from nodes
    with reference positions ``X`` (..., 2) and displacements ``un`` (..., 3): the offset
    turns with the node's rotation."""
    c, s = jnp.cos(un[..., 2]), jnp.sin(un[..., 2])
    turned = jnp.stack(
        [c * offset[..., 0] - s * offset[..., 1], s * offset[..., 0] + c * offset[..., 1]], axis=-1
    )
    return X + un[..., :2] + turned


@pytree()
class ContactParams:
    """Numeric parameters of a contact term (batchable leaves).

    Attributes:
        X: reference positions of the contact nodes, mm, (k, 2).
        substrate: the rigid substrate (a PyTree from :mod:`.substrates`).
        law: the :class:`FrictionLaw` (its limit, penalty stiffnesses).
        radius: contact radius of each point, mm, (k,): the point touches the substrate
            with a disc of this radius (0: the point itself).
        offset: reference offset of each contact point from its node, mm, (k, 2); it turns
            with the node's rotation, so a point on a beam's face (offset h/2 normal to the
            axis) stays on that face and the friction force's moment about the axis acts
            on the node's rotation.
    """

    X: Any
    substrate: Any
    law: Any
    radius: Any
    offset: Any


@pytree()
class ContactHistory:
    """Committed per-node history: stick anchor (mm, arc length on the substrate),
    cumulative frictional dissipation (mJ), state (0 open, 1 stick, 2 slip), normal force
    p_N (N) and tangential force f_t (N) of the last converged step."""

    anchor: Any
    dissipation: Any
    state: Any
    p_n: Any
    f_t: Any


def profile_top(substrate) -> jax.Array:
    """Height (mm) of the highest point of a substrate's surface: the largest vertex height
    of its profile (a fillet only lowers a convex corner, and a concave fillet lies between
    its two segments)."""
    return jnp.max(substrate.profile().vertices[..., 1], axis=-1)


@dataclasses.dataclass(frozen=True)
class SubstrateContact(Term):
    """Contact of points attached to the FE nodes ``nodes`` (static, hashable) with a rigid
    substrate. A node may carry several points (listed once per point, with different
    offsets in :class:`ContactParams`).

    ``active`` (static, optional): a broad phase with a fixed capacity. Each residual
    evaluates the projection and the return mapping for the ``active`` points that reach
    lowest (y minus the contact radius) only; the others get no force. That is exact
    while at most ``active`` points reach below the top of the substrate's profile (every
    other point then has a positive gap, so no force): :meth:`excess` counts the points
    beyond, and the solvers reject a converged state where it is not zero with status
    CONTACT_OVERFLOW, a failure that names the parameter to raise (a smaller step cannot
    cure it). The saving is the work on points that cannot touch (a bristle's points away
    from its tip). Default None: every point, always.
    """

    nodes: tuple[int, ...]
    active: int | None = None

    def __post_init__(self) -> None:
        if len(self.nodes) == 0:
            raise InputError("contact term needs at least one node")
        if self.active is not None and not (isinstance(self.active, int) and self.active >= 1):
            raise InputError(f"contact 'active' must be a whole number >= 1, got {self.active!r}")

    @staticmethod
    def params(
        model_X: np.ndarray, nodes, substrate, law: FrictionLaw, radius=0.0, offset=None
    ) -> ContactParams:
        """Parameters for ``nodes`` of a structure with reference positions ``model_X``;
        ``radius`` (mm) one value or one per point; ``offset`` (mm) None or (k, 2)."""
        X = jnp.asarray(np.asarray(model_X, float)[np.asarray(nodes, int), :2])
        k = X.shape[0]
        r = np.broadcast_to(np.asarray(radius, float), (k,))
        if not np.all(np.isfinite(r)) or np.any(r < 0):
            raise InputError("contact radius must be finite and >= 0 mm")
        off = np.zeros((k, 2)) if offset is None else np.asarray(offset, float)
        if off.shape != (k, 2) or not np.all(np.isfinite(off)):
            raise InputError(f"contact offsets must be finite, shape ({k}, 2)")
        return ContactParams(
            X=X, substrate=substrate, law=law, radius=jnp.asarray(r), offset=jnp.asarray(off)
        )

    def _x(self, u, params):
        return attached_points(params.X, u[jnp.asarray(self.nodes)], params.offset)

    #: The residual takes ``freeze`` (:func:`bristlecrawler.fe.newton.newton`).
    freezes = True

    def residual(self, u, v, t, history, params, freeze=False):
        """Contact forces on the nodes (internal-force sign, full (n_nodes, 3)). With
        ``freeze`` (a bool, traced or not) each closed point keeps the stick or slip
        status of the committed history instead of the return mapping's."""
        x, pull = jax.vjp(lambda u: self._x(u, params), u)
        mode = frozen_status(history.state, freeze)
        return pull(self.point_forces(x, history.anchor, params, mode))[0]

    def point_forces(self, x, anchor, params, mode=None):
        """Contact forces (N, (k, 2)) on the points at ``x`` (mm, (k, 2)) with stick anchors
        ``anchor``; with ``active``, through the broad phase (the same forces while
        :meth:`excess` is 0). ``mode``: frozen statuses (k,) or None."""

        def forces(x, anchor, radius, mode):
            axes = (0, 0, None, None, 0, None if mode is None else 0)
            return jax.vmap(point_force, in_axes=axes)(
                x, anchor, params.substrate, params.law, radius, mode
            )

        k = x.shape[0]
        if self.active is None or self.active >= k:
            return forces(x, anchor, params.radius, mode)
        reach = jax.lax.stop_gradient(x[:, 1] - params.radius)
        _, sel = jax.lax.top_k(-reach, self.active)
        # Gather and scatter by a one-hot matrix (active, k): cheap at these sizes, and it
        # keeps gather/scatter out of the linearised program.
        P = (sel[:, None] == jnp.arange(k)[None, :]).astype(x.dtype)
        m = None if mode is None else mode[sel]
        return P.T @ forces(P @ x, P @ anchor, P @ params.radius, m)

    def excess(self, u, params):
        """How many more points reach below the top of the profile than the broad phase
        evaluates (int; 0 when it is exact, always 0 without ``active``), at the full
        nodal displacements ``u``."""
        if self.active is None or self.active >= len(self.nodes):
            return jnp.asarray(0)
        x = self._x(u, params)
        below = jnp.sum(x[:, 1] - params.radius < profile_top(params.substrate))
        return jnp.maximum(below - self.active, 0)

    def penetration(self, history, params):
        """Deepest penetration (mm) of a committed history: p_N / k_N."""
        return params.law.penetration(jnp.max(history.p_n))

    def init_history(self, topology, params):
        """Anchors at the reference positions (a run that starts from the reference)."""
        return self.history_at(jnp.zeros((topology.n_nodes, 3)), params)

    def history_at(self, u, params):
        """Fresh history with every node stuck where it is at displacement ``u``; pass it
        to ``fe.initial_state(..., history=...)`` when a run starts away from the reference
        (otherwise the first step would see a slip from the reference position)."""
        s0 = jax.vmap(lambda p: project(params.substrate, p).arc_length)(self._x(u, params))
        z = jnp.zeros_like(s0)
        return ContactHistory(s0, z, jnp.zeros(s0.shape, jnp.int32), z, z)

    def commit(self, u, v, t, history, params):
        x = self._x(u, params)
        anchor, step = jax.vmap(node_step, in_axes=(0, 0, None, None, None, 0))(
            x, history.anchor, params.substrate, params.law, 0.0, params.radius
        )
        return ContactHistory(
            anchor,
            history.dissipation + step.dissipation,
            step.state.astype(jnp.int32),
            step.p_n,
            step.f_t,
        )
