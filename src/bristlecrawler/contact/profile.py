"""Closest-point projection onto a rigid periodic 2-D profile y = h(x) with filleted corners.

Every analytic substrate of the package (flat, grooves, sawtooth, polyline) is reduced to one
:class:`PeriodicProfile`: the vertices of a polyline over exactly one period plus a fillet
radius per vertex. The boundary of the solid (the region below the profile) is then a chain of
line segments and circular arcs; a sharp corner is an arc of radius zero. That single device
makes corners robust: the Voronoi region of a zero-radius convex arc is the cone between the
normals of its two segments, so for a point in that cone the closest point is the corner and
the normal is the direction from the corner to the point; for a concave corner the cone lies
inside the solid. The sign of the gap is taken from the primitive that is closest, which is
the pseudo-normal test of Baerentzen & Aanaes (IEEE TVCG 11(3), 2005) in 2-D.

The gap ``g`` is the signed distance to the solid: positive outside, negative when
penetrating, ``|grad g| = 1`` away from the medial axis and ``grad g = n``.
A period is handled by wrapping x into the reference period and testing the copies of the
primitives shifted by -1, 0, +1 periods: for x in the reference period and a feature in it,
the nearest copy of that feature is always one of those three.

Conventions: x horizontal, y up, lengths in mm. The profile is traversed towards +x with
the solid on the right, so the outward normal of a segment with direction d is
n = (-d_y, d_x) and the tangent is t = (n_y, -n_x) (towards increasing arc length).
"""

from __future__ import annotations

from typing import NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from bristlecrawler._pytree import as_float_leaf, is_concrete, pytree
from bristlecrawler.errors import InputError

# Ranking penalty (mm) for a candidate whose closest point was clamped to an end: such a point
# is also the end of the neighbouring primitive, which then owns it with the right normal.
_CLAMP_BIAS = 1e-9
# Candidates within this (relative) distance of the best are a tie, resolved by period order,
# so that round-off (e.g. after wrapping x into the period) cannot flip the choice.
_TIE = 1e-11
# Angular tolerance (rad) of the ranking's cone test: a point this close to the edge of an
# arc's cone counts as inside it.
_CONE_TOL = 1e-12
_TINY = 1e-300


class Projection(NamedTuple):
    """Closest-point projection of a query point (all arrays, float64).

    Attributes:
        gap: signed distance to the solid, mm (> 0 outside, < 0 penetrating).
        normal: outward unit normal at the closest point, (2,), equal to grad(gap).
        tangent: unit tangent (n_y, -n_x), pointing towards increasing arc length, (2,).
        point: closest point on the surface, mm, (2,).
        arc_length: arc-length coordinate of the closest point along the unrolled profile,
            mm, continuous across periods (0 at the first tangent point of the period).
        arc_gradient: d arc_length / d p, (2,), dimensionless: the tangent on a segment,
            +-``tangent r / |p - centre|`` on an arc, 0 in a corner's cone (the closest
            point stays put). The derivative autodiff gives, in closed form, so a
            contact force needs no Jacobian of the projection (and its tangent no second
            derivatives).
    """

    gap: jax.Array
    normal: jax.Array
    tangent: jax.Array
    point: jax.Array
    arc_length: jax.Array
    arc_gradient: jax.Array


@pytree()
class PeriodicProfile:
    """Periodic chain of segments and fillet arcs: the common form of every substrate.

    Attributes:
        vertices: (n + 1, 2) polyline over one period, mm; the last vertex is the first one
            shifted by one period (same y). x must not decrease (vertical walls allowed).
        fillets: (n,) fillet radius at vertices 0..n-1, mm (vertex n is vertex 0 of the next
            period); 0 for a sharp corner.

    The constructor does not check geometry (the substrate classes do); use
    :meth:`checked` for a user-supplied chain.
    """

    vertices: jax.Array
    fillets: jax.Array

    def __post_init__(self) -> None:
        as_float_leaf(self, "vertices")
        as_float_leaf(self, "fillets")

    def profile(self) -> PeriodicProfile:
        return self

    @property
    def period(self) -> jax.Array:
        """Period of the profile, mm."""
        return self.vertices[..., -1, 0] - self.vertices[..., 0, 0]

    def checked(self) -> PeriodicProfile:
        """Raise :class:`InputError` unless the chain is a valid periodic profile."""
        if is_concrete(self.vertices, self.fillets):
            check_vertices(np.asarray(self.vertices), "vertices")
        return self


def drawing(profile: PeriodicProfile, x0: float, x1: float) -> np.ndarray:
    """The surface as a polyline covering x0..x1 (mm), (K, 2), for figures: the periods'
    vertices, with the fillets (rounded corners) left out."""
    v = np.asarray(profile.vertices, dtype=float)
    period = float(v[-1, 0] - v[0, 0])
    k0 = int(np.floor((x0 - v[-1, 0]) / period))
    k1 = int(np.ceil((x1 - v[0, 0]) / period))
    shift = np.array([period, 0.0])
    tiles = [v[:-1] + k * shift for k in range(k0, k1 + 1)]
    return np.concatenate([*tiles, v[-1:] + k1 * shift])


def check_vertices(v: np.ndarray, name: str) -> None:
    """Validate a polyline over one period (shape (n+1, 2), or a batch (..., n+1, 2))."""
    v = np.asarray(v, dtype=float)
    if v.ndim < 2 or v.shape[-1] != 2 or v.shape[-2] < 2:
        raise InputError(f"{name} must have shape (n + 1, 2) with n >= 1, got {v.shape}")
    if not np.all(np.isfinite(v)):
        raise InputError(f"{name} must be finite")
    for poly in v.reshape(-1, *v.shape[-2:]):
        _check_one(poly, name)


def _check_one(v: np.ndarray, name: str) -> None:
    period = v[-1, 0] - v[0, 0]
    if not period > 0:
        raise InputError(f"{name}: last x must exceed first x (one period), got period {period}")
    if v[-1, 1] != v[0, 1]:
        raise InputError(
            f"{name}: not periodic, first y = {v[0, 1]} differs from last y = {v[-1, 1]}"
        )
    d = np.diff(v, axis=0)
    length = np.hypot(d[:, 0], d[:, 1])
    if np.any(length <= 1e-12 * period):
        i = int(np.argmax(length <= 1e-12 * period))
        raise InputError(f"{name}: points {i} and {i + 1} coincide (zero-length segment)")
    if np.any(d[:, 0] < 0):
        i = int(np.argmax(d[:, 0] < 0))
        raise InputError(
            f"{name}: x decreases from point {i} to {i + 1} (overhang or self-intersection)"
        )
    # With x non-decreasing the only way to cross itself is to fold back along a vertical
    # wall; check consecutive segments cyclically (the last one meets the first one).
    dn = np.roll(d, -1, axis=0)
    folds = (d[:, 0] == 0) & (dn[:, 0] == 0) & (d[:, 1] * dn[:, 1] < 0)
    if np.any(folds):
        i = int(np.argmax(folds))
        raise InputError(f"{name}: self-intersecting, the wall folds back at point {i + 1}")


def _rot90(d: jax.Array) -> jax.Array:
    return jnp.stack([-d[..., 1], d[..., 0]], axis=-1)


def cross(a: jax.Array, b: jax.Array) -> jax.Array:
    """The 2-D cross product a x b (its z component), over the last axis."""
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


def _unit(v: jax.Array) -> jax.Array:
    return v / jnp.sqrt(jnp.maximum(jnp.sum(v * v, axis=-1, keepdims=True), _TINY))


class ProfileChain(NamedTuple):
    """Segments and arcs of one period, derived from a :class:`PeriodicProfile`."""

    a: jax.Array  # (n, 2) segment starts (after the fillet tangent point), mm
    b: jax.Array  # (n, 2) segment ends, mm
    seg_normal: jax.Array  # (n, 2)
    seg_s0: jax.Array  # (n,) arc length at segment start, mm
    center: jax.Array  # (n, 2) arc centres, mm
    radius: jax.Array  # (n,) mm
    mid: jax.Array  # (n, 2) unit direction to the arc midpoint from the centre
    half: jax.Array  # (n,) half opening angle, rad
    orient: jax.Array  # (n,) +1 convex (solid inside the circle), -1 concave
    turn: jax.Array  # (n,) +1 counter-clockwise traversal, -1 clockwise, 0 straight
    arc_s0: jax.Array  # (n,) arc length at arc start, mm
    edge_plus: jax.Array  # (n, 2) unit direction of the arc's cone edge at psi = +half
    edge_minus: jax.Array  # (n, 2) the edge at psi = -half
    end_plus: jax.Array  # (n, 2) arc end at psi = +half, mm
    end_minus: jax.Array  # (n, 2) arc end at psi = -half, mm
    period: jax.Array  # mm
    x0: jax.Array  # mm
    length: jax.Array  # arc length of one period, mm


def profile_chain(prof: PeriodicProfile) -> ProfileChain:
    v = prof.vertices
    r = prof.fillets
    d = v[1:] - v[:-1]
    seg_len = jnp.sqrt(jnp.sum(d * d, axis=-1))
    dh = d / seg_len[:, None]
    n_out = _rot90(dh)
    n_in = jnp.roll(n_out, 1, axis=0)  # vertex i joins segment i-1 (cyclically) to segment i
    cr = cross(n_in, n_out)
    theta = jnp.arctan2(jnp.abs(cr), jnp.sum(n_in * n_out, axis=-1))
    half = 0.5 * theta
    orient = jnp.where(cr > 0, -1.0, 1.0)  # clockwise turn with solid on the right = convex
    turn = jnp.sign(cr)
    mid = orient[:, None] * _unit(n_in + n_out)
    center = v[:-1] - mid * (r / jnp.cos(half))[:, None]
    tang = r * jnp.tan(half)  # distance from a vertex to the fillet tangent points
    tang_next = jnp.roll(tang, -1)
    a = v[:-1] + tang[:, None] * dh
    b = v[1:] - tang_next[:, None] * dh
    line_len = seg_len - tang - tang_next
    arc_len = r * theta
    # Unrolled order in one period: segment 0, arc 1, segment 1, ..., arc n-1, segment n-1,
    # then arc 0 of the next period; so arc 0 of the reference copy ends at s = 0.
    arc_next = jnp.roll(arc_len, -1)
    seg_s0 = jnp.concatenate([jnp.zeros(1), jnp.cumsum(line_len + arc_next)[:-1]])
    arc_s0 = jnp.concatenate([-arc_len[:1], seg_s0[:-1] + line_len[:-1]])
    cos_h, sin_h = jnp.cos(half), jnp.sin(half)

    def edge(sign):
        return jnp.stack(
            [
                cos_h * mid[:, 0] - sign * sin_h * mid[:, 1],
                sign * sin_h * mid[:, 0] + cos_h * mid[:, 1],
            ],
            axis=-1,
        )

    return ProfileChain(
        a=a,
        b=b,
        seg_normal=n_out,
        seg_s0=seg_s0,
        center=center,
        radius=r,
        mid=mid,
        half=half,
        orient=orient,
        turn=turn,
        arc_s0=arc_s0,
        edge_plus=edge(1.0),
        edge_minus=edge(-1.0),
        end_plus=center + r[:, None] * edge(1.0),
        end_minus=center + r[:, None] * edge(-1.0),
        period=v[-1, 0] - v[0, 0],
        x0=v[0, 0],
        length=jnp.sum(line_len + arc_len),
    )


def _clip(x: jax.Array, lo: jax.Array, hi: jax.Array) -> jax.Array:
    # Unlike jnp.clip, keeps the full derivative at x == lo or hi (jnp.minimum splits it in
    # half at a tie, which would halve d(arc length)/dx at a vertex).
    return jnp.where(x < lo, lo, jnp.where(x > hi, hi, x))


def _segments(c: ProfileChain, p: jax.Array):
    ab = c.b - c.a
    ab2 = jnp.maximum(jnp.sum(ab * ab, axis=-1), _TINY)  # fillets may eat a whole segment
    t_raw = jnp.sum((p - c.a) * ab, axis=-1) / ab2
    t = _clip(t_raw, 0.0, 1.0)
    q = c.a + t[:, None] * ab
    signed = jnp.sum((p - q) * c.seg_normal, axis=-1)
    dist = jnp.sqrt(jnp.sum((p - q) ** 2, axis=-1))
    clamped = (t_raw < 0.0) | (t_raw > 1.0)
    s = c.seg_s0 + t * jnp.sqrt(ab2)
    # d s / d p: the unit direction inside the segment, 0 where t is clamped (_clip)
    ds = jnp.where(((t_raw >= 0.0) & (t_raw <= 1.0))[:, None], ab / jnp.sqrt(ab2)[:, None], 0.0)
    return dist, clamped, signed, c.seg_normal, q, s, ds


def _arcs(c: ProfileChain, p: jax.Array):
    v = p - c.center
    vv = jnp.sum(v * v, axis=-1, keepdims=True)
    away = vv > 1e-200
    v = jnp.where(away, v, c.mid)  # the angle at the centre itself is arbitrary
    psi = jnp.arctan2(cross(c.mid, v), jnp.sum(c.mid * v, axis=-1))
    psi_c = _clip(psi, -c.half, c.half)
    cos, sin = jnp.cos(psi_c), jnp.sin(psi_c)
    u = jnp.stack(
        [cos * c.mid[:, 0] - sin * c.mid[:, 1], sin * c.mid[:, 0] + cos * c.mid[:, 1]], axis=-1
    )
    q = c.center + c.radius[:, None] * u
    n = c.orient[:, None] * u
    signed = jnp.sum((p - q) * n, axis=-1)
    dist = jnp.sqrt(jnp.sum((p - q) ** 2, axis=-1))
    clamped = jnp.abs(psi) > c.half
    s = c.arc_s0 + c.radius * (c.half + c.turn * psi_c)
    # d s / d p = r turn d psi / d p, d psi / d p = (-v_y, v_x) / |v|^2 (0 where clamped)
    free = (psi >= -c.half) & (psi <= c.half) & away[:, 0]
    ds = jnp.where(
        free[:, None], (c.radius * c.turn)[:, None] * _rot90(v) / jnp.where(away, vv, 1.0), 0.0
    )
    return dist, clamped, signed, n, q, s, ds


def _distances(c: ProfileChain, p: jax.Array, m: jax.Array):
    """Distance from ``p`` (x in period ``m``) to every primitive of the copies -1, 0, +1 of
    the reference period, and whether its closest point is clamped to an end; each (6 n,)
    in the order (copy, segments then arcs, index). The values of :func:`_segments` and
    :func:`_arcs` (to round-off), without the rest: an arc's distance and clamp come from
    a cone test against its edges and its precomputed ends rather than from its angle, so
    no transcendental function is evaluated per candidate (this ranking is most of a
    projection's cost)."""
    k = m + jnp.array([-1.0, 0.0, 1.0])
    pk = p[None, :] - jnp.stack([k * c.period, jnp.zeros(3)], axis=-1)  # (3, 2)
    # segments as evaluated in full (no angles there; what the ranking does not use is
    # dropped by the compiler)
    seg_dist, seg_clamped = jax.vmap(lambda q: _segments(c, q)[:2])(pk)  # (3, n) each
    v = pk[:, None, :] - c.center[None]
    norm_v = jnp.sqrt(jnp.sum(v * v, axis=-1))
    # |psi| <= half as sin(psi - half) <= 0 <= sin(psi + half) and cos(psi) >= 0, from
    # cross products with the cone's edges, inclusive to _CONE_TOL rad: a point on an
    # edge (e.g. straight below a groove's concave bottom corner, in the solid) must rank
    # the corner's arc unclamped, whose normal gives the right sign, whatever the
    # round-off (a clamped segment end there has a zero signed distance).
    tol = _CONE_TOL * norm_v
    inside = (
        (cross(c.edge_plus, v) <= tol)
        & (cross(c.edge_minus, v) >= -tol)
        & (jnp.sum(c.mid * v, axis=-1) >= -tol)
    )
    end = jnp.where((cross(c.mid, v) > 0.0)[..., None], c.end_plus, c.end_minus)
    arc_dist = jnp.where(
        inside, jnp.abs(norm_v - c.radius), jnp.sqrt(jnp.sum((pk[:, None, :] - end) ** 2, -1))
    )
    dist = jnp.concatenate([seg_dist, arc_dist], axis=1).reshape(-1)
    clamped = jnp.concatenate([seg_clamped, ~inside], axis=1).reshape(-1)
    return dist, clamped


def _winner(c: ProfileChain, p: jax.Array, m: jax.Array) -> jax.Array:
    """Index (into :func:`_distances`' order) of the primitive closest to ``p``."""
    dist, clamped = _distances(c, p, m)
    rank = dist + _CLAMP_BIAS * clamped
    best = jnp.min(rank)
    return jnp.argmax(rank <= best + _TIE * (1.0 + best))


def _one(c: ProfileChain, p: jax.Array, m: jax.Array, i: jax.Array):
    """Primitive ``i`` (in :func:`_distances`' order) evaluated at ``p``: (dist, clamped,
    signed distance, normal, closest point, arc length, d arc length / d p)."""
    n = c.a.shape[0]
    k = (i // (2 * n)).astype(p.dtype) - 1.0
    is_arc = (i % (2 * n)) >= n
    # Pick primitive i % n by a masked sum (under vmap cheaper than a gather or a dot).
    pick = jnp.arange(n) == i % n
    per = ("a", "b", "seg_normal", "seg_s0", "center", "radius", "mid", "half", "orient")
    per = (*per, "turn", "arc_s0")

    def one(x):
        mask = pick.reshape(n, *([1] * (x.ndim - 1)))
        return jnp.sum(jnp.where(mask, x, 0.0), axis=0, keepdims=True)

    c1 = c._replace(**{f: one(getattr(c, f)) for f in per})
    shift = jnp.stack([(m + k) * c.period, 0.0])
    seg, arc = _segments(c1, p - shift), _arcs(c1, p - shift)
    dist, clamped, signed, nrm, q, s, ds = (
        jnp.where(is_arc, b_[0], a_[0]) for a_, b_ in zip(seg, arc, strict=True)
    )
    return dist, clamped, signed, nrm, q + shift, s + (m + k) * c.length, ds


def project(substrate, p: jax.Array) -> Projection:
    """Project one point ``p`` (2,), mm, onto a substrate (anything with ``.profile()``).

    Pure and traceable: ``jax.jit``, ``jax.vmap`` over points and over batches of substrate
    parameters, ``jax.grad`` of the gap (= normal away from the medial axis).
    At a tie between primitives (on the medial axis, to 1e-11 relative) the first one in
    period order wins, so the choice is consistent, e.g. on the bisector of a groove's
    bottom corner (the wall wins over the bottom).

    The closest primitive is chosen among all of them without derivatives (the choice is
    piecewise constant in ``p`` and in the substrate's parameters), then the projection is
    evaluated from that primitive alone: the same values and derivatives as the evaluation
    of every primitive, but a derivative (the contact tangent of an FE Newton iteration,
    pushed through many seeds) costs one primitive instead of 6 n.
    """
    c = profile_chain(substrate.profile())
    p = jnp.asarray(p, dtype=jnp.float64)
    m = jnp.floor((jax.lax.stop_gradient(p[0]) - c.x0) / c.period)
    i = _winner(jax.lax.stop_gradient(c), jax.lax.stop_gradient(p), jax.lax.stop_gradient(m))
    _, clamped, signed, n, q, s, ds = _one(c, p, m, i)
    # Normally the winner is not clamped and gap = (p - q).n is exact and smooth (also on
    # the surface). A clamped winner only happens on the boundary of a corner's cone (ties
    # within round-off): there (p - q).n may be 0 while |p - q| is not, so use the distance
    # and the direction q -> p (a safe sqrt keeps grad finite at the corner itself).
    diff = p - q
    d2 = jnp.sum(diff * diff)
    ok = d2 > 1e-30
    root = jnp.sqrt(jnp.where(ok, d2, 1.0))
    sign = jnp.where(signed < 0.0, -1.0, 1.0)
    use_dist = clamped & ok
    g = jnp.where(use_dist, sign * root, signed)
    normal = jnp.where(use_dist, sign * diff / root, n)
    tangent = jnp.stack([normal[1], -normal[0]])
    return Projection(gap=g, normal=normal, tangent=tangent, point=q, arc_length=s, arc_gradient=ds)


def gap(substrate, p: jax.Array) -> jax.Array:
    """Signed distance (mm) from ``p`` (2,) to the solid below the profile; see :func:`project`."""
    return project(substrate, p).gap


#: :func:`project` over many points ``(m, 2)``, compiled once per substrate type and shape.
project_points = jax.jit(jax.vmap(project, in_axes=(None, 0)))


_host_chain = jax.jit(profile_chain)


def convex_corners(substrate) -> tuple[np.ndarray, np.ndarray, float]:
    """Convex corners of one period of ``substrate``: centres (k, 2) mm, fillet radii (k,)
    mm, and the period (mm). Straight vertices and concave corners are not returned."""
    # One compiled program, not the chain's hundreds of eager operations: a batch builds
    # this for every design (each eager operation is a dispatch, on a GPU a launch).
    c = jax.device_get(_host_chain(substrate.profile()))
    turn = np.asarray(c.turn)
    orient = np.asarray(c.orient)
    keep = (turn != 0) & (orient > 0)
    centres = np.asarray(c.center)[keep]
    radii = np.asarray(c.radius)[keep]
    return centres, radii, float(c.period)
