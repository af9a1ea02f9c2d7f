"""Corner-to-outline contact: the substrate's convex corners against the outlines of beams.

Node-to-surface contact (:mod:`.term`) keeps beam *points* out of the substrate. A sharp
convex corner of a rigid substrate (the edge of a land between two grooves) can still pass
between two points and cut into the beam: with 40 elements on a 5 mm bristle the corner
sinks h_e^2 / (8 R) between nodes for a fillet R, tens of micrometres for R = 0.05 mm,
far more than the penalty's design penetration, and a bristle that should ride over the
corner locks and later snaps free. This term closes that gap with the dual pairing
(Wriggers 2006, Sec. 4.1, the master/slave roles swapped): every convex corner of the
substrate is a slave disc (centre and radius of its fillet, radius 0 when sharp) and the
master is the closed outline of a beam chain: its two faces through the face points of
the nodes (node position plus h/2 along the section normal, turning with the node's
rotation), the end face at the tip and the section at the clamp
(:func:`beam_outline`).

Per (outline, corner) pair:

* gap ``g`` = signed distance from the corner's centre to the outline polygon (negative
  inside the beam), minus the fillet radius; at a vertex the sign comes from the
  pseudo-normal (Baerentzen & Aanaes 2005), so the gap is continuous everywhere and
  differentiable except on the polygon's medial axis, which a contact reaches only at a
  penetration of half the local thickness.
* tangential coordinate ``s`` = reference arc length along the outline of the closest
  point, so the stick anchor is a material point of the beam's surface and "slip" is the
  corner sliding along it. The elastic slip and the slip increment are measured in
  *current* length along the outline, between the anchor's material point and the
  closest point (:func:`current_arc`), so the friction force is Coulomb's mu p_N on a
  stretched or compressed face and continuous across its vertices.

The Coulomb kernel is the one of the point contacts (:mod:`.coulomb`): penalty normal
force, return mapping with the anchor as history, exact dissipation ``mu p_N |Delta a|``.

The corners near an outline are a window of whole periods of the substrate, placed at
each committed step around the outline's current extent; the pairs of corners that stay
in the window are carried over, new ones start open. The window is fixed inside Newton
(the residual is a fixed function of the DOFs within a step), and a step moves a beam by
much less than the window's margin.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any

import jax
import jax.numpy as jnp
import numpy as np

from bristlecrawler._pytree import pytree
from bristlecrawler.contact.corner_tangent import WINDOW, near_forces
from bristlecrawler.contact.coulomb import (
    FrictionLaw,
    frozen_status,
)
from bristlecrawler.contact.outline import (
    clearance,
    current_arc,
    pair_gap,
    reference_arc,
    select_feature,
)
from bristlecrawler.contact.profile import convex_corners
from bristlecrawler.contact.term import attached_points
from bristlecrawler.errors import InputError
from bristlecrawler.fe.terms import Term


def beam_outline(chain, thickness, normal) -> tuple[tuple[int, ...], np.ndarray]:
    """Closed outline of a beam chain: ``(nodes, offsets)`` for :class:`FaceCornerContact`.

    ``chain`` node indices from clamp to tip, ``thickness`` (mm) at those nodes, ``normal``
    (2,) the unit section normal in the reference configuration. The loop runs along the
    +normal face from clamp to tip, across the end face, back along the -normal face, and
    closes across the clamp (its first point repeated at the end).
    """
    chain = tuple(int(c) for c in chain)
    half = 0.5 * np.asarray(thickness, float)[:, None] * np.asarray(normal, float)[None, :]
    nodes = chain + chain[::-1] + chain[:1]
    offsets = np.concatenate([half, -half[::-1], half[:1]])
    return nodes, offsets


@pytree()
class FaceParams:
    """Numeric parameters of a :class:`FaceCornerContact` (batchable leaves).

    Attributes:
        X: reference positions of the outline points' nodes, mm, (F, n, 2).
        offset: reference offset of each outline point from its node, mm, (F, n, 2).
        arc: reference arc length of the outline points along their outline, mm, (F, n).
        side: +1 or -1 per outline: outward normal = side * (d_y, -d_x) for a segment
            direction d (+1 for a counter-clockwise outline), (F,).
        corners: corner centres in one period of the substrate, mm, (k, 2).
        radii: corner fillet radii, mm, (k,).
        period: substrate period, mm.
        law: the :class:`FrictionLaw`.
    """

    X: Any
    offset: Any
    arc: Any
    side: Any
    corners: Any
    radii: Any
    period: Any
    law: Any


@pytree()
class FaceHistory:
    """Committed history: first period of each outline's corner window ``k0`` (F,), and
    per (outline, window corner) (F, m): stick anchor (mm of face arc length), cumulative
    dissipation (mJ), state (0 open, 1 stick, 2 slip), p_N (N) and f_t (N)."""

    k0: Any
    anchor: Any
    dissipation: Any
    state: Any
    p_n: Any
    f_t: Any


def _face_points(u, nodes, params):
    return attached_points(params.X, u[nodes], params.offset)


def _pulled(current, pull, law, drop=None, mode=None):
    """Nodal forces of pairs with (gap, current arc, anchor) ``current`` through the VJP
    ``pull`` of their geometry; pairs flagged in ``drop`` carry none. ``mode``: frozen
    statuses (:func:`~bristlecrawler.contact.coulomb.return_map`) or None."""
    fg, fs = law.forces(*current, mode=mode)
    if drop is not None:
        fg, fs = jnp.where(drop, 0.0, fg), jnp.where(drop, 0.0, fs)
    # The penalty energy depends on s - a: the anchor's material point moves with the
    # outline, so it takes -fs.
    return pull((fg, fs, -fs))[0]


@dataclasses.dataclass(frozen=True)
class FaceCornerContact(Term):
    """Contact of closed beam outlines ``faces`` (each a tuple of FE node indices, one per
    outline point, first repeated last: see :func:`beam_outline`; static, hashable) with
    the convex corners of a periodic rigid substrate, ``periods`` periods of corners in each
    outline's window.

    ``tangent_pairs``: pairs per outline whose forces are differentiated (see
    :meth:`residual`). ``local_tangent``: assemble their derivative from each pair's
    stiffness on its four outline points (:func:`.corner_tangent.near_forces`, which states where it
    is exact; about a third less time per Newton iteration of the paper crawler) rather
    than by differentiating through the whole outline (False: for comparison)."""

    faces: tuple[tuple[int, ...], ...]
    periods: int
    tangent_pairs: int = 4
    local_tangent: bool = True

    def __post_init__(self) -> None:
        if not self.faces or any(len(f) < 4 for f in self.faces):
            raise InputError("corner contact needs closed outlines of at least three points")
        if len({len(f) for f in self.faces}) != 1:
            raise InputError("corner contact: all outlines must have the same number of points")
        if any(f[0] != f[-1] for f in self.faces):
            raise InputError("corner contact: an outline must end at its first node")
        if self.periods < 1:
            raise InputError("corner contact: the corner window needs at least one period")
        if self.tangent_pairs < 1:
            raise InputError("corner contact: tangent_pairs must be >= 1")

    @staticmethod
    def window_periods(span: float, period: float, margin: float) -> int:
        """Periods a window needs to cover an outline of horizontal extent <= ``span`` (mm)
        with ``margin`` (mm) on both sides, wherever it sits on the period grid."""
        # The window starts up to one period before centre - periods * period / 2.
        return math.ceil((span + 2.0 * margin) / period) + 2

    @staticmethod
    def params(model_X, faces, offsets, substrate, law: FrictionLaw) -> FaceParams:
        """Parameters for the outlines ``faces`` of a structure with reference positions
        ``model_X``; ``offsets`` (F, n, 2) mm per outline point. ``substrate`` must have
        convex corners (:func:`convex_corners`): a term without any would never act, so
        the crawler and the drag test leave it out on such a substrate instead."""
        Xn = np.asarray(model_X, float)[:, :2]
        idx = np.asarray(faces, int)
        off = np.asarray(offsets, float)
        if off.shape != (*idx.shape, 2):
            raise InputError(f"corner contact: offsets must have shape {(*idx.shape, 2)}")
        if not np.all(np.isfinite(off)):
            raise InputError("corner contact: offsets must be finite")
        P = Xn[idx] + off
        seg = np.diff(P, axis=1)
        length = np.hypot(seg[..., 0], seg[..., 1])
        if np.any(length <= 0):
            raise InputError("corner contact: an outline has two coincident points")
        arc = np.concatenate([np.zeros((len(idx), 1)), np.cumsum(length, axis=1)], axis=1)
        area = 0.5 * np.sum(P[:, :-1, 0] * P[:, 1:, 1] - P[:, 1:, 0] * P[:, :-1, 1], axis=1)
        if np.any(np.abs(area) <= 0):
            raise InputError("corner contact: an outline encloses no area")
        side = np.sign(area)
        corners, radii, period = convex_corners(substrate)
        if len(corners) == 0:
            raise InputError("corner contact: the substrate has no convex corners")
        return FaceParams(
            X=jnp.asarray(Xn[idx]),
            offset=jnp.asarray(off),
            arc=jnp.asarray(arc),
            side=jnp.asarray(side),
            corners=jnp.asarray(corners),
            radii=jnp.asarray(radii),
            period=jnp.asarray(period),
            law=law,
        )

    # -- geometry ---------------------------------------------------------------------

    def _window(self, k0, params):
        """Corner centres (F, m, 2) and radii (F, m) of the windows starting at period k0."""
        k = params.corners.shape[0]
        per = k0[:, None] + jnp.arange(self.periods)[None, :]  # (F, P)
        shift = per[..., None] * params.period  # (F, P, 1)
        cx = params.corners[None, None, :, 0] + shift
        cy = jnp.broadcast_to(params.corners[None, None, :, 1], cx.shape)
        C = jnp.stack([cx, cy], axis=-1).reshape(len(self.faces), self.periods * k, 2)
        r = jnp.broadcast_to(params.radii, (len(self.faces), self.periods, k))
        return C, r.reshape(len(self.faces), self.periods * k)

    def _k0(self, u, params):
        P = self._points(u, params)
        xmin = jnp.min(P[..., 0], axis=1)
        xmax = jnp.max(P[..., 0], axis=1)
        centre = 0.5 * (xmin + xmax)
        c0 = jnp.min(params.corners[:, 0])
        # Window of `periods` periods centred on the face.
        first = centre - 0.5 * self.periods * params.period
        return jnp.floor((first - c0) / params.period).astype(jnp.int32)

    def _points(self, u, params):
        return _face_points(u, jnp.asarray(self.faces), params)

    def _gs(self, u, k0, params):
        return self._gs_at(self._points(u, params), k0, params)

    def _gs_at(self, P, k0, params):
        """Gap and reference arc coordinate of every (outline, window corner) pair for the
        outline points ``P`` (F, n + 1, 2)."""
        C, rho = self._window(k0, params)
        pair = jax.vmap(pair_gap, in_axes=(None, None, None, 0, 0))
        return jax.vmap(pair)(P, params.arc, params.side, C, rho)

    # -- term protocol ----------------------------------------------------------------

    def couplings(self) -> tuple[tuple[int, ...], ...]:
        """Node groups of the tangent (:mod:`bristlecrawler.fe.terms`): a pair reads the
        segment it projects on and the neighbouring outline points that set its vertex
        normals, four consecutive outline points (:func:`pair_gap`), i.e. up to four
        consecutive nodes of a bristle. Undeclared, the couplings two and three nodes
        apart fell outside the chain's block-tridiagonal band and were dropped from the
        tangent: Newton converged linearly (the residual halved per iteration, about 20
        iterations per step of the paper crawler)."""
        groups = set()
        for face in self.faces:
            n = len(face) - 1
            for i in range(n):
                groups.add(tuple(sorted({face[(i + d) % n] for d in WINDOW})))
        return tuple(sorted(groups))

    def _current(self, u, k0, anchor, params):
        """Gap (mm), current arc position of the closest point and of the stick anchor
        along the outline (mm of *current* length, :func:`current_arc`) of every pair."""
        return self._current_at(u, *self._window(k0, params), anchor, params)

    def _current_at(self, u, C, rho, anchor, params, sel=None):
        """:meth:`_current` of any k pairs per outline: corners ``C`` (F, k, 2), radii
        ``rho`` (F, k), anchors (F, k); ``sel``: their features (:meth:`_select`) where
        known."""
        P = self._points(u, params)
        if sel is None:
            sel = self._select(P, C, params)
        pair = jax.vmap(pair_gap, in_axes=(None, None, None, 0, 0, 0))
        g, s = jax.vmap(pair)(P, params.arc, params.side, C, rho, sel)
        to_cur = jax.vmap(current_arc, in_axes=(0, 0, 0))
        return g, to_cur(P, params.arc, s), to_cur(P, params.arc, anchor)

    @staticmethod
    def _select(P, C, params):
        """The feature of its outline each corner ``C`` (F, k, 2) projects on
        (:func:`~bristlecrawler.contact.outline.select_feature`, per pair; no derivatives)."""
        sg = jax.lax.stop_gradient
        per_face = jax.vmap(select_feature, in_axes=(None, None, 0))
        return jax.vmap(per_face)(sg(P), params.side, sg(C))

    def _force(self, u, C, rho, anchor, params, mode=None):
        return self._force_and_current(u, C, rho, anchor, params, mode)[0]

    def _force_and_current(self, u, C, rho, anchor, params, mode=None):
        """Nodal forces of the pairs with corners ``C`` (F, k, 2), their (gap, current
        arc, current anchor) and their features (:meth:`_select`)."""
        sel = self._select(self._points(u, params), C, params)
        current, pull = jax.vjp(lambda u: self._current_at(u, C, rho, anchor, params, sel), u)
        return _pulled(current, pull, params.law, mode=mode), current, sel

    #: The residual takes ``freeze`` (:func:`bristlecrawler.fe.newton.newton`).
    freezes = True

    def residual(self, u, v, t, history, params, freeze=False):
        """Forces of every pair; the derivative (the Newton tangent) is taken through the
        ``tangent_pairs`` pairs of each outline with the smallest clearances only
        (:func:`~bristlecrawler.contact.outline.clearance`, a lower bound on the gap).

        An open pair (g > 0) has zero force and zero stiffness, and an outline touches a
        few corners at a time, so the tangent is exact while at most ``tangent_pairs``
        pairs of an outline have a clearance <= 0; beyond that the tangent lacks the
        others' stiffness, the residual is still the full one, and Newton converges to
        the same state, more slowly. Linearising every pair (14 per bristle of the paper
        crawler) cost 1.6 ms of a 2.3 ms tangent extraction.

        Broad phase: the exact geometry of the other pairs is evaluated only when one of
        them has a clearance <= 0 (it may touch); otherwise their forces are zero and
        are not computed. On the paper crawler this saved 10-15 % of a Newton iteration
        (the same iterates).

        With ``freeze`` (a bool, traced or not) each closed pair keeps the stick or slip
        status of the committed history instead of the return mapping's.
        """
        C, rho = self._window(history.k0, params)
        mode = frozen_status(history.state, freeze)
        m = C.shape[1]
        if self.tangent_pairs >= m:
            return self._force(u, C, rho, history.anchor, params, mode)
        u0 = jax.lax.stop_gradient(u)
        # Broad phase: a cheap lower bound on every pair's gap chooses the differentiated
        # pairs; the exact geometry of all pairs is evaluated only where a pair left out
        # may touch (rare: at most two pairs per outline were ever closed on the paper
        # crawler), and then adds the forces of the others as before.
        lb = jax.vmap(clearance)(self._points(u0, params), C, rho)
        _, idx = jax.lax.top_k(-lb, self.tangent_pairs)  # (F, k): the closest corners

        def take(x):
            return jnp.take_along_axis(x, idx.reshape(*idx.shape, *([1] * (x.ndim - 2))), 1)

        chosen = jnp.zeros(lb.shape, bool).at[jnp.arange(lb.shape[0])[:, None], idx].set(True)
        near = (near_forces if self.local_tangent else FaceCornerContact._force)(
            self,
            u,
            take(C),
            take(rho),
            take(history.anchor),
            params,
            None if mode is None else take(mode),
        )

        def others(_):
            current, pull = jax.vjp(
                lambda u: self._current_at(u, C, rho, history.anchor, params), u0
            )
            return _pulled(current, pull, params.law, drop=chosen, mode=mode)

        may_touch = jnp.any(~chosen & ~(lb > 0.0))
        rest = jax.lax.cond(may_touch, others, lambda _: jnp.zeros_like(u0), None)
        return near + jax.lax.stop_gradient(rest)

    def penetration(self, history, params):
        """Deepest penetration (mm) of a committed history: p_N / k_N."""
        return params.law.penetration(jnp.max(history.p_n))

    def init_history(self, topology, params):
        return self.history_at(jnp.zeros((topology.n_nodes, 3)), params)

    def history_at(self, u, params):
        """Fresh history at displacement ``u``: windows around the faces, all pairs open
        with their anchors at the current closest points."""
        k0 = self._k0(u, params)
        _, s = self._gs(u, k0, params)
        z = jnp.zeros_like(s)
        return FaceHistory(k0, s, z, jnp.zeros(s.shape, jnp.int32), z, z)

    def commit(self, u, v, t, history, params):
        g, s, a = self._current(u, history.k0, history.anchor, params)
        step = params.law.step(g, s, a)
        # Back to the anchor's material (reference) arc coordinate.
        P = self._points(u, params)
        to_ref = jax.vmap(reference_arc, in_axes=(0, 0, 0))
        step = step._replace(anchor=to_ref(P, params.arc, step.anchor))
        # Re-centre the windows; carry over the pairs whose corner stays in the window.
        k0 = self._k0(u, params)
        k = params.corners.shape[0]
        shift = (k0 - history.k0)[:, None] * k  # old slot = new slot + shift
        m = self.periods * k
        old = jnp.arange(m)[None, :] + shift
        kept = (old >= 0) & (old < m)
        oi = jnp.clip(old, 0, m - 1)

        def carry(a):
            return jnp.take_along_axis(a, oi, axis=1)

        _, s_new = self._gs_at(P, k0, params)
        anchor = jnp.where(kept, carry(step.anchor), s_new)
        # Dissipation is per slot; what leaves the window is added to the face's first slot
        # so that the sum over a face stays cumulative.
        diss = history.dissipation + step.dissipation
        total = jnp.sum(diss, axis=1)
        diss = jnp.where(kept, carry(diss), 0.0)
        diss = diss.at[:, 0].add(total - jnp.sum(diss, axis=1))
        return FaceHistory(
            k0,
            anchor,
            diss,
            jnp.where(kept, carry(step.state.astype(jnp.int32)), 0),
            jnp.where(kept, carry(step.p_n), 0.0),
            jnp.where(kept, carry(step.f_t), 0.0),
        )
