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

from bristlecrawler.contact._pytree import pytree_dataclass
from bristlecrawler.contact.coulomb import CoulombLaw, generalized_forces, return_map
from bristlecrawler.contact.profile import _chain, _cross
from bristlecrawler.contact.term import attached_points
from bristlecrawler.errors import InputError

jax.config.update("jax_enable_x64", True)

#: A vertex of an outline whose two segments' normals differ by more than 45 degrees is a
#: corner of the section (end faces), not a kink of a bent face: normals are not blended.
_SHARP_COS = math.cos(math.pi / 4)


def convex_corners(substrate) -> tuple[np.ndarray, np.ndarray, float]:
    """Convex corners of one period of ``substrate``: centres (k, 2) mm, fillet radii (k,)
    mm, and the period (mm). Straight vertices and concave corners are not returned."""
    c = _chain(substrate.profile())
    turn = np.asarray(c.turn)
    orient = np.asarray(c.orient)
    keep = (turn != 0) & (orient > 0)
    centres = np.asarray(c.center)[keep]
    radii = np.asarray(c.radius)[keep]
    return centres, radii, float(c.period)


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


@pytree_dataclass
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
        law: the :class:`CoulombLaw`.
    """

    X: Any
    offset: Any
    arc: Any
    side: Any
    corners: Any
    radii: Any
    period: Any
    law: Any


@pytree_dataclass
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


def _normals(P, side):
    """Segment normals (n, 2) of the closed polygon P (n + 1 points), the previous segment's
    normals, the sharp-vertex flags (n,) and the blended vertex normals (n, 2)."""
    ab = P[1:] - P[:-1]
    L = jnp.sqrt(jnp.maximum(jnp.sum(ab * ab, axis=-1), 1e-300))
    n_seg = side * jnp.stack([ab[:, 1], -ab[:, 0]], axis=-1) / L[:, None]
    n_prev = jnp.roll(n_seg, 1, axis=0)  # vertex k joins segments k - 1 and k (cyclic)
    sharp = jnp.sum(n_prev * n_seg, axis=-1) < _SHARP_COS
    nv = n_seg + n_prev
    nv = nv / jnp.sqrt(jnp.maximum(jnp.sum(nv * nv, axis=-1, keepdims=True), 1e-300))
    return n_seg, n_prev, sharp, nv


def _fan(A, B, nA, nB, C):
    """Parameter t on segment AB (any leading shape) whose interpolated normal line
    passes through C: the root of (C - A - t AB) x (nA + t (nB - nA)) = 0 nearest the
    segment, in the cancellation-free form."""
    ab = B - A
    dn = nB - nA
    w = C - A
    a2 = -_cross(ab, dn)
    a1 = _cross(w, dn) - _cross(ab, nA)
    a0 = _cross(w, nA)
    disc = jnp.maximum(a1 * a1 - 4.0 * a2 * a0, 0.0)
    root = jnp.sqrt(jnp.where(disc > 1e-300, disc, 1.0)) * (disc > 1e-300)
    den = a1 + jnp.where(a1 < 0.0, -1.0, 1.0) * root
    den = jnp.where(jnp.abs(den) > 1e-300, den, 1e-300)
    return -2.0 * a0 / den


def _select(P, side, C):
    """Which feature of the polygon the corner C projects on (no derivatives needed: the
    choice is piecewise constant): (segment i, sharp vertex k, fallback segment m, found,
    segment wins, sign at the vertex)."""
    n_seg, n_prev, sharp, nv = _normals(P, side)
    A, B = P[:-1], P[1:]
    ab = B - A
    nA = jnp.where(sharp[:, None], n_seg, nv)
    nB = jnp.where(jnp.roll(sharp, -1)[:, None], n_seg, jnp.roll(nv, -1, axis=0))
    t = _fan(A, B, nA, nB, C)
    inside = (t >= 0.0) & (t <= 1.0)
    d = C - (A + t[:, None] * ab)
    d2 = jnp.where(inside, jnp.sum(d * d, axis=-1), jnp.inf)
    dv = C - A
    dv2 = jnp.where(sharp, jnp.sum(dv * dv, axis=-1), jnp.inf)
    i = jnp.argmin(d2)
    k = jnp.argmin(dv2)
    seg_wins = d2[i] <= dv2[k]
    found = jnp.isfinite(jnp.minimum(d2[i], dv2[k]))
    vsign = jnp.where(jnp.dot(dv[k], n_seg[k] + n_prev[k]) < 0.0, -1.0, 1.0)
    L2 = jnp.maximum(jnp.sum(ab * ab, axis=-1), 1e-300)
    tc = jnp.clip(jnp.sum((C - A) * ab, axis=-1) / L2, 0.0, 1.0)
    dc = C - (A + tc[:, None] * ab)
    m = jnp.argmin(jnp.sum(dc * dc, axis=-1))
    return i, k, m, found, seg_wins, vsign


def _pair(P, arc, side, C, rho):
    """Gap (mm) and outline arc coordinate (mm) of a corner disc (C, rho) against the
    closed polygon P (first point repeated at the end), with interpolated normals.

    A plain closest-point projection on a polygon is continuous in the gap but not in the
    arc coordinate: on the concave side of a vertex (a face wrapped around the corner that
    presses into it is concave there) the closest point jumps from one segment to the next
    by about ``depth x kink angle``, and the stick spring turns that into a force jump of
    ``k_t depth kink`` that no step size removes. Here each segment AB carries the normal
    interpolated linearly between the vertex normals (the normalised sums of the adjacent
    segments' normals), and the corner's parameter t on AB solves
    ``(C - A - t AB) x (n_A + t (n_B - n_A)) = 0``: the ray from the point at t along the
    interpolated normal passes through C. Vertex normals are shared by adjacent segments,
    so t, the arc coordinate and the gap ``(C - x(t)) . n(t) / |n(t)| - rho`` are
    continuous across vertices (Wriggers 2006, Sec. 9.1 on smoothed master surfaces, in
    the normal-interpolation form). Vertices where the outline turns by more than 45
    degrees (the corners of the end faces) are not smoothed: there each segment keeps its
    own normal and the vertex is a candidate of its own (closest point = the vertex, for
    the wedge between the normals). The nearest candidate wins; where none reaches C (far
    from the outline) the plain closest point is used.

    The feature is chosen on the whole polygon without derivatives (:func:`_select`); the
    gap and arc coordinate are then evaluated from the (at most four) outline points that
    define it. Values and derivatives are those of the evaluation on the whole polygon
    (the choice is piecewise constant), but the tangent, pushed through ``3 bs`` seeds by
    the FE Newton, costs four points per pair instead of the whole outline.
    """
    n = P.shape[0] - 1
    i, k, m, found, seg_wins, vsign = _select(
        jax.lax.stop_gradient(P), side, jax.lax.stop_gradient(C)
    )
    # Segment i: its end points and the neighbouring ones that set the vertex normals.
    Q = P[jnp.stack([(i - 1) % n, i, i + 1, (i + 2) % n])]
    # Normals of segments i - 1, i, i + 1 and the blended normals at vertices i, i + 1
    # (computed one by one: a cyclic roll over Q would blend segments i - 1 and i + 1,
    # opposite faces of a thin end, whose zero sum makes second derivatives NaN).
    ab = Q[1:] - Q[:-1]
    L = jnp.sqrt(jnp.maximum(jnp.sum(ab * ab, axis=-1), 1e-300))
    n_loc = side * jnp.stack([ab[:, 1], -ab[:, 0]], axis=-1) / L[:, None]
    sharp_i = jnp.sum(n_loc[0] * n_loc[1]) < _SHARP_COS
    sharp_j = jnp.sum(n_loc[1] * n_loc[2]) < _SHARP_COS

    def blend(a, b):
        # Only used where the two normals are within 45 degrees; the double where keeps
        # the derivatives finite where they are opposite and the value is discarded.
        v = a + b
        v2 = jnp.sum(v * v)
        ok = v2 > 1e-12
        return jnp.where(ok, v / jnp.sqrt(jnp.where(ok, v2, 1.0)), a)

    nA = jnp.where(sharp_i, n_loc[1], blend(n_loc[0], n_loc[1]))
    nB = jnp.where(sharp_j, n_loc[1], blend(n_loc[1], n_loc[2]))
    A, B = Q[1], Q[2]
    t = _fan(A, B, nA, nB, C)
    x = A + t * (B - A)
    nt = nA + t * (nB - nA)
    nt = nt / jnp.sqrt(jnp.maximum(jnp.sum(nt * nt), 1e-300))
    g_seg = jnp.dot(C - x, nt)
    s_seg = arc[i] + t * (arc[i + 1] - arc[i])
    # Sharp vertex k: distance, signed by the pseudo-normal.
    dv = C - P[k]
    dv2 = jnp.sum(dv * dv)
    ok = dv2 > 1e-30
    vdist = jnp.where(ok, jnp.sqrt(jnp.where(ok, dv2, 1.0)), 0.0)
    # Fallback where no fan and no sharp vertex reaches C (far outside a smooth outline):
    # the distance to the nearest segment.
    Am, Bm = P[m], P[m + 1]
    abm = Bm - Am
    tc = jnp.clip(jnp.dot(C - Am, abm) / jnp.maximum(jnp.dot(abm, abm), 1e-300), 0.0, 1.0)
    dc = C - (Am + tc * abm)
    dc2 = jnp.sum(dc * dc)
    okc = dc2 > 1e-30
    g_far = jnp.where(okc, jnp.sqrt(jnp.where(okc, dc2, 1.0)), 0.0)
    g = jnp.where(found, jnp.where(seg_wins, g_seg, vsign * vdist), g_far) - rho
    s_far = arc[m] + tc * (arc[m + 1] - arc[m])
    s = jnp.where(found, jnp.where(seg_wins, s_seg, arc[k]), s_far)
    return g, s


def _cumulative(P):
    seg = P[1:] - P[:-1]
    L = jnp.sqrt(jnp.maximum(jnp.sum(seg * seg, axis=-1), 1e-300))
    return jnp.concatenate([jnp.zeros(1), jnp.cumsum(L)])


def current_arc(P, arc, s):
    """Current arc length (mm) along the polygon ``P`` (n + 1 points) of the points at
    reference arc coordinates ``s`` (mm; ``arc`` (n + 1,) the points' reference arc).

    Friction is measured in current length: a slip coordinate in *reference* arc length
    makes the friction force on a segment stretched by lambda equal to mu p_N / lambda
    (not Coulomb's mu p_N), and makes it jump where the closest point crosses a vertex
    between segments of different stretch. On the paper crawler at alpha = 0 that jump,
    0.029 N at a bent tip, stopped Newton at every step size (|R|/F alternating between
    6e-5 and 7.6e-3 at dt = 2 us). The anchor stays a material point (reference arc) in
    the history and is mapped with the current metric here."""
    return jnp.interp(s, arc, _cumulative(P))


def reference_arc(P, arc, c):
    """Inverse of :func:`current_arc`: reference arc coordinate (mm) of current arc ``c``."""
    return jnp.interp(c, _cumulative(P), arc)


@dataclasses.dataclass(frozen=True)
class FaceCornerContact:
    """Contact of closed beam outlines ``faces`` (each a tuple of FE node indices, one per
    outline point, first repeated last: see :func:`beam_outline`; static, hashable) with
    the convex corners of a periodic rigid substrate, ``periods`` periods of corners in each
    outline's window."""

    faces: tuple[tuple[int, ...], ...]
    periods: int
    tangent_pairs: int = 4

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
    def params(model_X, faces, offsets, substrate, law: CoulombLaw) -> FaceParams:
        """Parameters for the outlines ``faces`` of a structure with reference positions
        ``model_X``; ``offsets`` (F, n, 2) mm per outline point."""
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
        pair = jax.vmap(_pair, in_axes=(None, None, None, 0, 0))
        return jax.vmap(pair)(P, params.arc, params.side, C, rho)

    # -- term protocol ----------------------------------------------------------------

    def couplings(self) -> tuple[tuple[int, ...], ...]:
        """Node groups of the tangent (:mod:`bristlecrawler.fe.terms`): a pair reads the
        segment it projects on and the neighbouring outline points that set its vertex
        normals, four consecutive outline points (:func:`_pair`), i.e. up to four
        consecutive nodes of a bristle. Undeclared, the couplings two and three nodes
        apart fell outside the chain's block-tridiagonal band and were dropped from the
        tangent: Newton converged linearly (the residual halved per iteration, about 20
        iterations per step of the paper crawler)."""
        groups = set()
        for face in self.faces:
            n = len(face) - 1
            for i in range(n):
                groups.add(tuple(sorted({face[(i + d) % n] for d in (-1, 0, 1, 2)})))
        return tuple(sorted(groups))

    def _current(self, u, k0, anchor, params):
        """Gap (mm), current arc position of the closest point and of the stick anchor
        along the outline (mm of *current* length, :func:`current_arc`) of every pair."""
        return self._current_at(u, *self._window(k0, params), anchor, params)

    def _current_at(self, u, C, rho, anchor, params):
        """:meth:`_current` of any k pairs per outline: corners ``C`` (F, k, 2), radii
        ``rho`` (F, k), anchors (F, k)."""
        P = self._points(u, params)
        pair = jax.vmap(_pair, in_axes=(None, None, None, 0, 0))
        g, s = jax.vmap(pair)(P, params.arc, params.side, C, rho)
        to_cur = jax.vmap(current_arc, in_axes=(0, 0, 0))
        return g, to_cur(P, params.arc, s), to_cur(P, params.arc, anchor)

    def _force(self, u, C, rho, anchor, params, keep=None):
        (g, s, a), pull = jax.vjp(lambda u: self._current_at(u, C, rho, anchor, params), u)
        fg, fs = generalized_forces(g, s, a, params.law)
        if keep is not None:
            fg, fs = jnp.where(keep, fg, 0.0), jnp.where(keep, fs, 0.0)
        # The penalty energy depends on s - a: the anchor's material point moves with the
        # outline, so it takes -fs.
        return pull((fg, fs, -fs))[0]

    def residual(self, u, v, t, history, params):
        """Forces of every pair; the derivative (the Newton tangent) is taken through the
        ``tangent_pairs`` pairs of each outline with the smallest gaps only.

        An open pair (g > 0) has zero force and zero stiffness, and an outline touches a
        few corners at a time, so the tangent is exact while at most ``tangent_pairs``
        pairs of an outline are closed; beyond that the tangent lacks the others'
        stiffness, the residual is still the full one, and Newton converges to the same
        state, more slowly. Linearising every pair (14 per bristle of the paper crawler)
        cost 1.6 ms of a 2.3 ms tangent extraction.
        """
        C, rho = self._window(history.k0, params)
        m = C.shape[1]
        if self.tangent_pairs >= m:
            return self._force(u, C, rho, history.anchor, params)
        u0 = jax.lax.stop_gradient(u)
        g0 = self._current_at(u0, C, rho, history.anchor, params)[0]
        _, idx = jax.lax.top_k(-g0, self.tangent_pairs)  # (F, k): the closest corners

        def take(x):
            return jnp.take_along_axis(x, idx.reshape(*idx.shape, *([1] * (x.ndim - 2))), 1)

        chosen = jnp.zeros(g0.shape, bool).at[jnp.arange(g0.shape[0])[:, None], idx].set(True)
        near = self._force(u, take(C), take(rho), take(history.anchor), params)
        rest = self._force(u0, C, rho, history.anchor, params, keep=~chosen)
        return near + jax.lax.stop_gradient(rest)

    def penetration(self, history, params):
        """Deepest penetration (mm) of a committed history: p_N / k_N."""
        return jnp.max(history.p_n) / params.law.k_n

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
        step = return_map(g, s, a, params.law)
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
