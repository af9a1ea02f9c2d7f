"""Geometry of a corner against a beam's closed outline (for :mod:`.corner`).

A substrate corner (a disc: centre and fillet radius) against the closed polygon of a
beam's outline: the outline's segment normals (blended at the kinks of a bent face, not
at the section's corners), the closest point and the signed gap with the pseudo-normal
sign, the reference arc length of the closest point, and the conversions between the
reference arc length and the *current* length along the outline.
"""

from __future__ import annotations

import math

import jax
import jax.numpy as jnp

from bristlecrawler.contact.profile import cross
from bristlecrawler.fe.motion import interp

#: A vertex of an outline whose two segments' normals differ by more than 45 degrees is a
#: corner of the section (end faces), not a kink of a bent face: normals are not blended.
_SHARP_COS = math.cos(math.pi / 4)

#: Round-off allowance on a segment's fan parameter t in [0, 1] (see :func:`select_feature`).
_T_EPS = 1e-12


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
    a2 = -cross(ab, dn)
    a1 = cross(w, dn) - cross(ab, nA)
    a0 = cross(w, nA)
    disc = jnp.maximum(a1 * a1 - 4.0 * a2 * a0, 0.0)
    root = jnp.sqrt(jnp.where(disc > 1e-300, disc, 1.0)) * (disc > 1e-300)
    den = a1 + jnp.where(a1 < 0.0, -1.0, 1.0) * root
    den = jnp.where(jnp.abs(den) > 1e-300, den, 1e-300)
    return -2.0 * a0 / den


def _segment_distance2(A, ab, C):
    """Squared distance (mm^2) from C (2,), or (k, 1, 2) for k points, to each segment
    A + t ab, t in [0, 1] (A, ab: (n, 2)); shape (n,) or (k, n)."""
    L2 = jnp.maximum(jnp.sum(ab * ab, axis=-1), 1e-300)
    t = jnp.clip(jnp.sum((C - A) * ab, axis=-1) / L2, 0.0, 1.0)
    d = C - (A + t[..., None] * ab)
    return jnp.sum(d * d, axis=-1)


def select_feature(P, side, C):
    """Which feature of the polygon the corner C projects on (no derivatives needed: the
    choice is piecewise constant): (segment i, sharp vertex k, fallback segment m, found,
    segment wins, sign at the vertex)."""
    n_seg, n_prev, sharp, nv = _normals(P, side)
    A, B = P[:-1], P[1:]
    ab = B - A
    nA = jnp.where(sharp[:, None], n_seg, nv)
    nB = jnp.where(jnp.roll(sharp, -1)[:, None], n_seg, jnp.roll(nv, -1, axis=0))
    t = _fan(A, B, nA, nB, C)
    # Inclusive to round-off: a corner on the normal line of a shared vertex has t = 1 on
    # one segment and t = 0 on the next, and both came out just outside [0, 1] (-1e-17,
    # 1 + 2e-16); the opposite face's segment, whose normal line (taken both ways by the
    # fan) also passes through the corner, then won and gave a gap of the wrong sign.
    inside = (t >= -_T_EPS) & (t <= 1.0 + _T_EPS)
    d = C - (A + jnp.clip(t, 0.0, 1.0)[:, None] * ab)
    d2 = jnp.where(inside, jnp.sum(d * d, axis=-1), jnp.inf)
    dv = C - A
    dv2 = jnp.where(sharp, jnp.sum(dv * dv, axis=-1), jnp.inf)
    i = jnp.argmin(d2)
    k = jnp.argmin(dv2)
    seg_wins = d2[i] <= dv2[k]
    found = jnp.isfinite(jnp.minimum(d2[i], dv2[k]))
    vsign = jnp.where(jnp.dot(dv[k], n_seg[k] + n_prev[k]) < 0.0, -1.0, 1.0)
    m = jnp.argmin(_segment_distance2(A, ab, C))
    return i, k, m, found, seg_wins, vsign


def _gap_at(A, B, nA, nB, C, t):
    """Distance (mm) from C to the point at t on segment AB along the normal interpolated
    there (positive on the side the normals point to)."""
    x = A + t * (B - A)
    nt = nA + t * (nB - nA)
    nt = nt / jnp.sqrt(jnp.maximum(jnp.sum(nt * nt), 1e-300))
    return jnp.dot(C - x, nt)


@jax.custom_jvp
def _held_gap(A, B, nA, nB, C, t):
    """:func:`_gap_at`, whose first derivatives hold the point t fixed.

    The gap's value is the distance along the interpolated normal at the fan root t; its
    derivatives are taken with t held: the normal force acts along n(t) on the corner
    and through the shape functions on the segment's ends. With t varying, dg/dt =
    -AB . n(t) is not zero (an interpolated normal is not normal to its segment), and
    the force got a component along the face of about p_N times the half turn of the
    outline at a vertex, with opposite signs on the two sides: the nodal forces jumped
    when the closest point crossed a vertex (0.018 N at p_N = 0.34 N on the vertical
    crawler), and a corner stuck on a vertex left Newton no root at any step size. The
    rule is itself differentiated with t(P, C) varying, so the Newton tangent (a
    derivative of these forces) stays exact.
    """
    return _gap_at(A, B, nA, nB, C, t)


@_held_gap.defjvp
def _held_gap_jvp(primals, tangents):
    *args, t = primals
    return jax.jvp(lambda *a: _gap_at(*a, t), tuple(args), tuple(tangents[:-1]))


def pair_gap(P, arc, side, C, rho, sel=None):
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

    The feature is chosen on the whole polygon without derivatives (:func:`select_feature`); the
    gap and arc coordinate are then evaluated from the (at most four) outline points that
    define it. Values and derivatives are those of the evaluation on the whole polygon
    (the choice is piecewise constant), but the tangent, pushed through ``3 bs`` seeds by
    the FE Newton, costs four points per pair instead of the whole outline. ``sel``: that
    choice where already made.
    """
    n = P.shape[0] - 1
    if sel is None:
        sel = select_feature(jax.lax.stop_gradient(P), side, jax.lax.stop_gradient(C))
    i, k, m = sel[:3]
    # Segment i: its end points and the neighbouring ones that set the vertex normals.
    Q = P[jnp.stack([(i - 1) % n, i, i + 1, (i + 2) % n])]
    ends = (arc[i], arc[i + 1], arc[k], arc[m], arc[m + 1])
    return feature_gap(Q, P[k], P[m], P[m + 1], ends, side, C, rho, sel)


def feature_gap(Q, Pk, Pm, Pm1, ends, side, C, rho, sel):
    """Gap (mm) and reference arc coordinate (mm) of :func:`pair_gap` on the feature ``sel``
    (:func:`select_feature`) chose: ``Q`` the outline points i - 1 ... i + 2 around segment i,
    ``Pk`` the sharp vertex k, ``Pm``, ``Pm1`` the ends of the fallback segment m, and
    ``ends`` the reference arc of points i, i + 1, k, m, m + 1. Only these points enter
    the values and their derivatives, whatever the outline
    (:class:`~bristlecrawler.contact.corner.FaceCornerContact` linearises a pair on them)."""
    _, _, _, found, seg_wins, vsign = sel
    arc_i, arc_i1, arc_k, arc_m, arc_m1 = ends
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
    g_seg = _held_gap(A, B, nA, nB, C, t)
    s_seg = arc_i + t * (arc_i1 - arc_i)
    # Sharp vertex k: distance, signed by the pseudo-normal.
    dv = C - Pk
    dv2 = jnp.sum(dv * dv)
    ok = dv2 > 1e-30
    vdist = jnp.where(ok, jnp.sqrt(jnp.where(ok, dv2, 1.0)), 0.0)
    # Fallback where no fan and no sharp vertex reaches C (far outside a smooth outline):
    # the distance to the nearest segment.
    abm = Pm1 - Pm
    tc = jnp.clip(jnp.dot(C - Pm, abm) / jnp.maximum(jnp.dot(abm, abm), 1e-300), 0.0, 1.0)
    dc = C - (Pm + tc * abm)
    dc2 = jnp.sum(dc * dc)
    okc = dc2 > 1e-30
    g_far = jnp.where(okc, jnp.sqrt(jnp.where(okc, dc2, 1.0)), 0.0)
    g = jnp.where(found, jnp.where(seg_wins, g_seg, vsign * vdist), g_far) - rho
    s_far = arc_m + tc * (arc_m1 - arc_m)
    s = jnp.where(found, jnp.where(seg_wins, s_seg, arc_k), s_far)
    return g, s


def clearance(P, C, rho):
    """Lower bound (mm) on the gap of each corner disc (C (k, 2), rho (k,)) against the
    closed polygon P (n + 1 points), -inf where the corner's centre lies inside it.

    Outside, every branch of :func:`pair_gap` measures the gap as the length of a line from
    the corner's centre to a point of the polygon (along an interpolated normal, to a
    sharp vertex, or to the closest point), minus rho, with the sign of the side. That
    length is at least the Euclidean distance to the polygon, so ``distance - rho > 0``
    leaves a pair open wherever the sign is the outside one; inside (crossing number) no
    bound is claimed. No derivatives: it only chooses which pairs to evaluate.
    """
    A, B = P[:-1], P[1:]
    ab = B - A
    dist = jnp.sqrt(jnp.min(_segment_distance2(A, ab, C[:, None, :]), axis=-1))
    # Crossing number of the ray from C towards +x.
    ya, yb = A[:, 1], B[:, 1]
    cy = C[:, None, 1]
    straddles = (ya > cy) != (yb > cy)
    dy = jnp.where(straddles, yb - ya, 1.0)
    x_cross = A[:, 0] + (cy - ya) * ab[:, 0] / dy
    crossings = jnp.sum(straddles & (C[:, None, 0] < x_cross), axis=-1)
    return jnp.where(crossings % 2 == 1, -jnp.inf, dist - rho)


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
    return interp(s, arc, _cumulative(P))


def reference_arc(P, arc, c):
    """Inverse of :func:`current_arc`: reference arc coordinate (mm) of current arc ``c``."""
    return interp(c, _cumulative(P), arc)
