"""The corner term's Newton tangent from each pair's four outline points.

:class:`~bristlecrawler.contact.corner.FaceCornerContact` differentiates the forces of a
few pairs per outline. Pushed through the whole outline (its face points, the arc-length
maps, the scatter into every node), that linearisation was close to half of a Newton
iteration of the paper crawler. A pair's forces depend only on the four outline points
around the feature its corner projects on (:data:`WINDOW`, the coupling groups the term
declares) and the current arc length between its stick anchor and its closest point, so
:func:`near_forces` assembles the derivative from one 12 x 12 stiffness per pair
(:func:`window_stiffness`).
"""

from __future__ import annotations

import functools

import jax
import jax.numpy as jnp
from jax.custom_derivatives import SymbolicZero, zero_from_primal

from bristlecrawler.contact.outline import feature_gap
from bristlecrawler.contact.term import attached_points

#: Outline points a pair reads, relative to the first point c of its feature (segment c,
#: sharp vertex c, fallback segment c): c - 1 ... c + 2 (:func:`~.outline.feature_gap`).
#: The term declares these groups as its couplings, and the local tangent reads them.
WINDOW = (-1, 0, 1, 2)


def window_stiffness(term, u, C, rho, anchor, params, mode, current, sel):
    """Stiffness of the pairs with corners ``C`` (F, k, 2) on the outline points that
    define them: ``(nodes, K)``, the FE nodes (F, k, 4) of the four consecutive
    outline points around each pair's feature and ``K`` (F, k, 4, 3, 4, 3), the
    derivative of the pair's forces on those points' nodes with respect to their
    displacements (copies of one node, at the tip, counted apart). ``current``: the
    pairs' (gap, current arc, current anchor) on the whole outline (their values);
    ``sel``: their features (:meth:`~.corner.FaceCornerContact._select`)."""
    n = params.arc.shape[1] - 1
    i, k, m, found, seg_wins, _ = sel
    # The feature's first point: segment i, sharp vertex k or fallback segment m; its
    # pair reads the outline points c - 1 ... c + 2 (the coupling groups declared).
    c = jnp.where(found, jnp.where(seg_wins, i, k), m)
    raw = c[..., None] + jnp.asarray(WINDOW)  # (F, k, 4)
    idx = raw % n
    f = jnp.arange(len(term.faces))[:, None, None]
    nodes = jnp.asarray(term.faces)[f, idx]
    total = params.arc[:, n][:, None, None]
    # Reference arc of the window, unwrapped across the outline's closing point.
    arcw = params.arc[f, idx] + total * (raw // n)
    g0, d0 = current[0], current[1] - current[2]

    def pair_force(uw, Xw, offw, arcw, side, C, rho, a, sel, g0, d0, mode):
        def geometry(uw):
            Pw = attached_points(Xw, uw, offw)
            ends = (arcw[1], arcw[2], arcw[1], arcw[1], arcw[2])
            g, s = feature_gap(Pw, Pw[1], Pw[1], Pw[2], ends, side, C, rho, sel)
            # Current length from the anchor to the closest point along the window's
            # three segments: current_arc's difference wherever both lie in them, in a
            # form without its search (a sum over the three segments). An anchor
            # across the outline's closing point (the clamp section, where no corner
            # reaches) is not unwrapped; the whole outline's arc is not periodic there
            # either.
            seg = Pw[1:] - Pw[:-1]
            L = jnp.sqrt(jnp.maximum(jnp.sum(seg * seg, axis=-1), 1e-300))
            lo, da = arcw[:-1], arcw[1:] - arcw[:-1]

            def cur(x):
                return jnp.sum(L * jnp.clip((x - lo) / da, 0.0, 1.0))

            d = cur(s) - cur(a)
            # The values of the whole outline's evaluation (exactly, so the friction
            # branch is the residual's), the derivatives of this one.
            sg = jax.lax.stop_gradient
            return sg(g0) + (g - sg(g)), sg(d0) + (d - sg(d))

        (g, d), pull = jax.vjp(geometry, uw)
        fg, fs = params.law.forces(g, d, 0.0, mode=mode)
        return pull((fg, fs))[0]

    def stiffness(*args):
        return jax.jacfwd(pair_force)(*args)

    per_pair = jax.vmap(stiffness, in_axes=(0, 0, 0, 0, None, 0, 0, 0, 0, 0, 0, 0))
    Xw, offw = params.X[f, idx], params.offset[f, idx]
    modes = jnp.full(c.shape, -1) if mode is None else mode
    K = jax.vmap(per_pair)(
        u[nodes], Xw, offw, arcw, params.side, C, rho, anchor, sel, g0, d0, modes
    )
    return nodes, K


@functools.partial(jax.custom_jvp, nondiff_argnums=(0,))
def near_forces(term, u, C, rho, anchor, params, mode):
    """:meth:`~.corner.FaceCornerContact._force` of the differentiated pairs, whose derivative in
    ``u`` is assembled from each pair's stiffness on its four outline points
    (:func:`window_stiffness`) instead of being pushed through the
    whole outline.

    The values are the same. The derivative is the same wherever a pair's stick anchor
    lies on the three segments around its feature (a step slides a corner along a face by
    a fraction of a segment); beyond, it lacks the stretch of the segments in between:
    couplings outside the groups the term declares, which the banded colouring could not
    hold anyway (they would alias into other entries of their colour). A tangent that is a product
    through the whole outline (jacfwd of the residual, the coloured JVPs of the Newton
    tangent) then costs a gather, one 12 x 12 product per pair and a scatter per seed.
    Any other argument's tangent (not zero) takes the whole outline's derivative.
    """
    return term._force(u, C, rho, anchor, params, mode)


def _symbolic_zero(x) -> bool:
    return isinstance(x, SymbolicZero)


def _is_zero(t) -> bool:
    return all(_symbolic_zero(x) for x in jax.tree_util.tree_leaves(t, is_leaf=_symbolic_zero))


@functools.partial(near_forces.defjvp, symbolic_zeros=True)
def _near_forces_jvp(term, primals, tangents):
    u, C, rho, anchor, params, mode = primals
    if not _is_zero(tangents[1:]):
        leaves, tree = jax.tree_util.tree_flatten(primals)
        dleaves = jax.tree_util.tree_leaves(tangents, is_leaf=_symbolic_zero)
        dleaves = [
            zero_from_primal(p) if _symbolic_zero(d) else d
            for p, d in zip(leaves, dleaves, strict=True)
        ]
        whole = term._force
        return jax.jvp(whole, primals, jax.tree_util.tree_unflatten(tree, dleaves))
    out, current, sel = term._force_and_current(u, C, rho, anchor, params, mode)
    du = tangents[0]
    if _symbolic_zero(du):
        return out, jnp.zeros_like(out)
    nodes, K = window_stiffness(term, u, C, rho, anchor, params, mode, current, sel)
    dfw = jnp.einsum("fpaibj,fpbj->fpai", K, du[nodes])
    return out, jnp.zeros_like(out).at[nodes].add(dfw)
