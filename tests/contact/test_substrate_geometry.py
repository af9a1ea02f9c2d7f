"""Signed distance, normals and closest points on rigid analytic substrates.

Oracles are independent of the implementation: hand-computed points, a parametrisation of
the grooved boundary written here, reflection/complement symmetries, periodicity, and a
brute-force distance to a densely sampled polyline.
"""

import itertools
import math

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from bristlecrawler.contact import (
    Flat,
    Grooves,
    Polyline,
    Sawtooth,
    gap,
    project,
    project_points,
)

grad_gap = jax.jit(jax.grad(gap, argnums=1))
gap_one = jax.jit(gap)
project_one = jax.jit(project)

G = Grooves(width=1.0, depth=0.25, pitch=2.0)  # groove over 0 <= x <= 1, land at y = 0


@pytest.mark.parametrize(
    ("p", "g", "n", "q"),
    [
        ((-0.5, 0.1), 0.1, (0, 1), (-0.5, 0.0)),  # above the land
        ((-0.5, -0.1), -0.1, (0, 1), (-0.5, 0.0)),  # below the land
        ((0.5, -0.1), 0.15, (0, 1), (0.5, -0.25)),  # inside the groove, bottom nearest
        ((0.05, -0.1), 0.05, (1, 0), (0.0, -0.1)),  # inside the groove near the left wall
        ((0.97, -0.2), 0.03, (-1, 0), (1.0, -0.2)),  # near the right wall
        ((-0.05, -0.1), -0.05, (1, 0), (0.0, -0.1)),  # penetrating the left wall
        ((0.5, -5.0), -4.75, (0, 1), (0.5, -0.25)),  # deep below the groove
        ((0.3, 0.4), 0.5, (0.6, 0.8), (0.0, 0.0)),  # convex corner: direction corner->point
        ((1.3, 0.4), 0.4, (0, 1), (1.3, 0.0)),  # above the land right of the groove
        ((0.7, 0.4), 0.5, (-0.6, 0.8), (1.0, 0.0)),  # right convex corner
        (
            (-0.1, -0.3),
            -math.hypot(0.1, 0.05),
            (0.8944271909999159, 0.4472135954999579),
            (0.0, -0.25),
        ),  # inside the solid under the concave bottom corner
        ((2.05, -0.1), 0.05, (1, 0), (2.0, -0.1)),  # next period
        ((-1.95, -0.1), 0.05, (1, 0), (-2.0, -0.1)),  # previous period
    ],
)
def test_grooves_hand_computed(p, g, n, q):
    pr = project_one(G, jnp.array(p))
    assert float(pr.gap) == pytest.approx(g, abs=1e-12)
    np.testing.assert_allclose(pr.normal, n, atol=1e-12)
    np.testing.assert_allclose(pr.point, q, atol=1e-12)
    np.testing.assert_allclose(pr.tangent, (n[1], -n[0]), atol=1e-12)


def test_concave_corner_tie_is_consistent():
    # On the bisector of the bottom-left corner (inside the groove) wall and bottom tie;
    # the same one must be picked every time, and the gap is the same either way.
    p = jnp.array([0.1, -0.15])
    a, b = project_one(G, p), project_one(G, p + jnp.array([2.0, 0.0]))
    assert float(a.gap) == pytest.approx(0.1)
    np.testing.assert_array_equal(a.normal, b.normal)


def _groove_params():
    return st.tuples(
        st.floats(0.2, 3.0),  # pitch
        st.floats(0.1, 0.9),  # width / pitch
        st.floats(0.05, 1.0),  # depth
        st.floats(0.0, 1.0),  # fillet_top / its bound
        st.floats(0.0, 1.0),  # fillet_bottom / its bound
        st.floats(-2.0, 2.0),  # phase
    ).map(_make_grooves)


def _make_grooves(t):
    p, wf, d, ft, fb, ph = t
    w = wf * p
    rb = fb * min(0.5 * w, 0.5 * d)
    rt = ft * min(0.5 * w, 0.5 * (p - w), d - rb)
    return Grooves(width=w, depth=d, pitch=p, phase=ph, fillet_top=rt, fillet_bottom=rb)


def _boundary_point(gr, u):
    """Point, outward normal and safe offsets (outwards, inwards) at u in [0, 1) of a period.

    Independent parametrisation of the filleted groove (written for the test), walking
    left land -> top fillet -> wall -> bottom fillet -> bottom -> ... -> right land. The safe
    offsets keep q + delta n closer to q than to the medial axis: on a straight piece the
    distance to its ends (corners are 90 degrees), on an arc its radius towards the centre.
    """
    w, d, p, ph = (float(x) for x in (gr.width, gr.depth, gr.pitch, gr.phase))
    rt, rb = float(gr.fillet_top), float(gr.fillet_bottom)
    q2 = 0.5 * math.pi

    def line(start, direction, normal, length):
        def f(s):
            q = np.array(start) + s * np.array(direction)
            lim = min(s, length - s)
            return q, np.array(normal, dtype=float), lim, lim

        return length, f

    def arc(c, r, a0, orient):
        def f(s):
            ang = a0 - orient * s / r if r > 0 else a0  # convex: clockwise
            u = np.array([math.cos(ang), math.sin(ang)])
            # convex (orient 1): the centre is inside; concave: outside. Away from the centre,
            # a sharp corner at an end of the arc (wall of zero length) limits like a line.
            ends = min(s, q2 * r - s)
            return (
                np.array(c) + r * u,
                orient * u,
                (ends if orient > 0 else r),
                (r if orient > 0 else ends),
            )

        return q2 * r, f

    x0 = ph - 0.5 * (p - w)
    land = 0.5 * (p - w) - rt
    wall = d - rt - rb
    pieces = [
        line((x0, 0.0), (1, 0), (0, 1), land),
        arc((ph - rt, -rt), rt, q2, 1),
        line((ph, -rt), (0, -1), (1, 0), wall),
        arc((ph + rb, -d + rb), rb, math.pi, -1),
        line((ph + rb, -d), (1, 0), (0, 1), w - 2 * rb),
        arc((ph + w - rb, -d + rb), rb, 1.5 * math.pi, -1),
        line((ph + w, -d + rb), (0, 1), (-1, 0), wall),
        arc((ph + w + rt, -rt), rt, math.pi, 1),
        line((ph + w + rt, 0.0), (1, 0), (0, 1), land),
    ]
    s = u * sum(x[0] for x in pieces)
    for length, f in pieces:
        if s <= length:
            return f(s)
        s -= length
    return pieces[-1][1](pieces[-1][0])


@given(gr=_groove_params(), u=st.floats(0.0, 1.0), frac=st.floats(-0.9, 0.9))
def test_offset_along_normal_projects_back(gr, u, frac):
    """q + delta n projects back to q with gap delta and normal n, and the gradient of the
    gap there matches central finite differences."""
    q, n, lim_out, lim_in = _boundary_point(gr, u)
    w, d, p = float(gr.width), float(gr.depth), float(gr.pitch)
    size = 0.5 * min(w, d, p - w)
    delta = frac * min(size, lim_out if frac > 0 else lim_in)
    x = q + delta * n
    pr = project_one(gr, jnp.array(x))
    assert float(pr.gap) == pytest.approx(delta, abs=1e-10)
    np.testing.assert_allclose(pr.point, q, atol=1e-9)
    np.testing.assert_allclose(pr.normal, n, atol=1e-9)
    h = 1e-6
    margin = min(size, lim_out, lim_in) - abs(delta)
    if margin > 10 * h:
        fd = [
            (gap_one(gr, jnp.array(x + h * e)) - gap_one(gr, jnp.array(x - h * e))) / (2 * h)
            for e in np.eye(2)
        ]
        np.testing.assert_allclose(fd, n, atol=1e-6)


@pytest.mark.slow
@given(gr=_groove_params(), x=st.floats(-10, 10), y=st.floats(-2, 1))
def test_closest_point_on_surface_and_gradient_is_normal(gr, x, y):
    p = jnp.array([x, y])
    pr = project_one(gr, p)
    # p = q + g n, |n| = 1, the closest point lies on the surface (gap 0 there)
    np.testing.assert_allclose(pr.point + pr.gap * pr.normal, p, atol=1e-10)
    assert float(jnp.linalg.norm(pr.normal)) == pytest.approx(1.0, abs=1e-12)
    assert float(project_one(gr, pr.point).gap) == pytest.approx(0.0, abs=1e-10)
    # jax.grad of the gap is the normal (|grad g| = 1); on the surface itself (a corner of a
    # tiny fillet, say) the direction p - q is round-off, so only check off the surface.
    if abs(float(pr.gap)) > 1e-9:
        np.testing.assert_allclose(grad_gap(gr, p), pr.normal, atol=1e-10)


@given(gr=_groove_params(), x=st.floats(-5, 5), y=st.floats(-2, 1), k=st.integers(-50, 50))
def test_periodicity(gr, x, y, k):
    p = jnp.array([x, y])
    a = project_one(gr, p)
    b = project_one(gr, p + jnp.array([k * float(gr.pitch), 0.0]))
    assert float(b.gap) == pytest.approx(float(a.gap), abs=1e-9)
    if abs(float(a.gap)) > 1e-9:  # on the surface of a tiny fillet the normal is round-off
        np.testing.assert_allclose(b.normal, a.normal, atol=1e-7)
    # one period of arc length: lands + walls, each 90 degree fillet trades 2r for pi r / 2
    rt, rb = float(gr.fillet_top), float(gr.fillet_bottom)
    per = float(gr.pitch) + 2 * float(gr.depth) - (4 - math.pi) * (rt + rb)
    if abs(float(a.gap)) > 1e-6:  # a point on the medial axis may pick another foot
        assert float(b.arc_length - a.arc_length) == pytest.approx(k * per, abs=1e-8)


@given(
    p=st.floats(0.2, 3.0),
    d=st.floats(0.05, 1.0),
    fr=st.floats(0.0, 1.0),
    x=st.floats(-5, 5),
    y=st.floats(-2, 1),
)
def test_complement_symmetry(p, d, fr, x, y):
    """With width = pitch/2 and equal fillets the air is the solid turned upside down and
    shifted by half a pitch, so g(x, y) = -g(x + p/2, -d - y): convex and concave corners
    swap roles."""
    r = fr * min(0.25 * p, 0.5 * d)
    gr = Grooves(width=0.5 * p, depth=d, pitch=p, fillet_top=r, fillet_bottom=r)
    g1 = project_one(gr, jnp.array([x, y])).gap
    g2 = project_one(gr, jnp.array([x + 0.5 * p, -d - y])).gap
    assert float(g1) == pytest.approx(-float(g2), abs=1e-9)


@given(gr=_groove_params(), x=st.floats(-5, 5), y=st.floats(-2, 1))
def test_mirror_symmetry(gr, x, y):
    # Grooves centred on x = 0 are symmetric: g(-x, y) = g(x, y), n_x flips.
    c = Grooves(
        width=gr.width,
        depth=gr.depth,
        pitch=gr.pitch,
        phase=-0.5 * gr.width,
        fillet_top=gr.fillet_top,
        fillet_bottom=gr.fillet_bottom,
    )
    a, b = project_one(c, jnp.array([x, y])), project_one(c, jnp.array([-x, y]))
    assert float(a.gap) == pytest.approx(float(b.gap), abs=1e-9)
    # off the mirror axes (x = k pitch / 2) the normals mirror each other; on them the
    # medial-axis tie is broken the same way on both sides, so they need not.
    half = 0.5 * float(gr.pitch)
    if abs(x / half - round(x / half)) * half > 1e-6:
        np.testing.assert_allclose(a.normal, b.normal * np.array([-1.0, 1.0]), atol=1e-6)


@given(
    w=st.floats(0.1, 2.0),
    d=st.floats(0.05, 1.0),
    fx=st.floats(0.001, 0.999),
    fy=st.floats(0.001, 0.999),
)
def test_gap_inside_sharp_groove_is_distance_to_nearest_wall_or_bottom(w, d, fx, fy):
    gr = Grooves(width=w, depth=d, pitch=w + 1.0, phase=0.3)
    x, y = 0.3 + fx * w, -fy * d
    expected = min(x - 0.3, 0.3 + w - x, y + d)
    assert float(project_one(gr, jnp.array([x, y])).gap) == pytest.approx(expected, abs=1e-12)


@given(h=st.floats(-10, 10), x=st.floats(-100, 100), y=st.floats(-10, 10))
def test_flat(h, x, y):
    pr = project_one(Flat(height=h), jnp.array([x, y]))
    assert float(pr.gap) == pytest.approx(y - h, abs=1e-10)
    np.testing.assert_allclose(pr.normal, (0.0, 1.0), atol=1e-12)
    assert float(pr.arc_length) == pytest.approx(x, abs=1e-9)


def test_fillet_geometry():
    r1, r2 = 0.1, 0.05
    gr = Grooves(width=1.0, depth=0.25, pitch=2.0, fillet_top=r1, fillet_bottom=r2)
    # the sharp convex corner was cut off: it is outside by r (sqrt 2 - 1), normal at 45 deg
    top = project_one(gr, jnp.array([0.0, 0.0]))
    assert float(top.gap) == pytest.approx(r1 * (math.sqrt(2) - 1), abs=1e-12)
    np.testing.assert_allclose(top.normal, np.array([1.0, 1.0]) / math.sqrt(2), atol=1e-12)
    # the sharp concave corner is now inside the filled fillet
    bot = project_one(gr, jnp.array([0.0, -0.25]))
    assert float(bot.gap) == pytest.approx(-r2 * (math.sqrt(2) - 1), abs=1e-12)
    np.testing.assert_allclose(bot.normal, np.array([1.0, 1.0]) / math.sqrt(2), atol=1e-12)
    # any point of the top fillet circle is on the surface, with normal centre -> point
    for ang in np.linspace(0.0, 0.5 * math.pi, 7):
        u = np.array([math.cos(ang), math.sin(ang)])
        pr = project_one(gr, jnp.array(np.array([-r1, -r1]) + (r1 + 0.02) * u))
        assert float(pr.gap) == pytest.approx(0.02, abs=1e-12)
        np.testing.assert_allclose(pr.normal, u, atol=1e-12)
    # the fillet is tangent to the land and to the wall: normals are continuous
    for x in (-r1 - 1e-9, -r1 + 1e-9):
        np.testing.assert_allclose(project_one(gr, jnp.array([x, 0.01])).normal, (0, 1), atol=1e-7)


def _brute_force_gap(points, p, period):
    """Signed distance to a polyline sampled at 20 000 points per period, 3 periods."""
    shifts = np.array([[k * period, 0.0] for k in (-1, 0, 1)])
    pts = np.vstack([points[:-1] + sh for sh in shifts] + [points[-1:] + shifts[-1]])
    seg = []
    for a, b in itertools.pairwise(pts):
        t = np.linspace(0.0, 1.0, 2000)[:, None]
        seg.append(a + t * (b - a))
    s = np.concatenate(seg)
    x = p[0] - period * np.floor((p[0] - points[0, 0]) / period)
    d = np.min(np.hypot(s[:, 0] - x, s[:, 1] - p[1]))
    inside = p[1] < np.interp(x, pts[:, 0], pts[:, 1])
    return -d if inside else d


@pytest.mark.slow
@given(
    pitch=st.floats(0.5, 3.0),
    height=st.floats(0.1, 1.0),
    f=st.floats(0.05, 0.95),
    x=st.floats(-3, 3),
    y=st.floats(-1.5, 1.5),
)
def test_sawtooth_matches_brute_force(pitch, height, f, x, y):
    saw = Sawtooth(pitch=pitch, height=height, rise_fraction=f)
    pts = np.array([[0.0, 0.0], [f * pitch, height], [pitch, 0.0]])
    ref = _brute_force_gap(pts, np.array([x, y]), pitch)
    g = float(project_one(saw, jnp.array([x, y])).gap)
    assert g == pytest.approx(ref, abs=2e-3 * pitch)


@pytest.mark.slow
def test_polyline_with_vertical_walls_matches_grooves():
    # A polyline describing the paper's grooves gives the same answer as Grooves.
    poly = Polyline(points=[[-0.5, 0], [0, 0], [0, -0.25], [1, -0.25], [1, 0], [1.5, 0]])
    rng = np.random.default_rng(0)
    pts = jnp.array(rng.uniform([-3, -1], [3, 0.5], size=(500, 2)))
    a, b = project_points(poly, pts), project_points(G, pts)
    np.testing.assert_allclose(a.gap, b.gap, atol=1e-12)
    np.testing.assert_allclose(a.point, b.point, atol=1e-12)


@pytest.mark.slow
def test_vmap_over_designs_and_one_compilation():
    widths = jnp.linspace(0.2, 1.8, 9)
    # a batch of designs: every field batched (stack single designs leaf by leaf)
    designs = [Grooves(width=w, depth=0.25, pitch=2.0) for w in widths]
    batch = jax.tree.map(lambda *x: jnp.stack(x), *designs)
    p = jnp.array([0.15, -0.1])
    many = jax.jit(jax.vmap(project, in_axes=(0, None)))(batch, p)
    for i, w in enumerate(widths):
        one = project_one(Grooves(width=w, depth=0.25, pitch=2.0), p)
        assert float(many.gap[i]) == pytest.approx(float(one.gap), abs=1e-12)
    # new designs of the same structure reuse the compiled kernel
    f = jax.jit(jax.vmap(project, in_axes=(None, 0)))
    pts = jnp.zeros((4, 2))
    f(Grooves(width=1.0, depth=0.25, pitch=2.0), pts)
    f(Grooves(width=0.5, depth=0.1, pitch=1.0, fillet_top=0.05), pts)
    assert f._cache_size() == 1


def _inner_path(r, depth, n=400):
    """Points ``depth`` inside the solid around the land edge at (0, 0) (land x < 0, wall
    x = 0 going down), from the land top to the wall; for a fillet of radius r the path
    is the parallel curve (straight, arc of radius r - depth, straight)."""
    c = np.array([-r, -r])
    pts = [np.array([x, -depth]) for x in np.linspace(-0.1, -r, n // 4)]
    if r > 0:
        pts += [
            c + (r - depth) * np.array([np.sin(a), np.cos(a)])
            for a in np.linspace(0.0, 0.5 * np.pi, n // 2)
        ]
    else:
        pts += [np.array([-depth, -depth])]
    pts += [np.array([-depth, y]) for y in np.linspace(-r, -0.1, n // 4)]
    return jnp.asarray(np.array(pts))


def _turns(n):
    """Angles (rad) between consecutive unit normals ``n`` (m, 2)."""
    return np.arccos(np.clip(np.sum(n[1:] * n[:-1], axis=1), -1.0, 1.0))


@pytest.mark.slow
def test_a_filleted_edge_turns_the_normal_continuously_inside_the_solid():
    # A point pressed into the solid near a land edge (penetration ~1e-3 mm in the crawler):
    # with a fillet r >> depth its normal turns smoothly as it moves round the edge, by at
    # most the arc step over the parallel curve's radius r - depth.
    r, depth = 0.02, 1e-3
    p = _inner_path(r, depth)
    res = project_points(Grooves(width=1.0, depth=0.25, pitch=2.0, fillet_top=r), p)
    np.testing.assert_allclose(np.asarray(res.gap), -depth, atol=1e-12)
    n = np.asarray(res.normal)
    turn = _turns(n)
    step = np.linalg.norm(np.diff(np.asarray(p), axis=0), axis=1)
    assert np.all(turn <= 1.01 * step / (r - depth) + 1e-9)
    np.testing.assert_allclose(n[0], [0.0, 1.0], atol=1e-12)  # land top
    np.testing.assert_allclose(n[-1], [1.0, 0.0], atol=1e-12)  # wall, facing the groove


@pytest.mark.slow
def test_a_sharp_edge_flips_the_normal_on_its_bisector():
    # The documented reason for the scenarios' fillet: at a sharp edge the closest point of
    # a penetrating point jumps from the land top to the wall on the bisector, so a point
    # pushed into the wall just below the edge, deeper in the wall than below the top, is
    # pushed up over the land rather than back into the groove.
    depth = 1e-3
    res = project_points(G, _inner_path(0.0, depth))
    n = np.asarray(res.normal)
    turn = np.degrees(_turns(n))
    assert turn.max() == pytest.approx(90.0, abs=1e-6)
    up = project_one(G, jnp.array([-0.004, -0.002]))  # 4 um into the wall, 2 um below the top
    np.testing.assert_allclose(np.asarray(up.normal), [0.0, 1.0], atol=1e-12)


# --- the ranking's cheap distances and the closed-form arc-length gradient -------------------


@jax.jit
def _full_ranking(gr, p):
    """Distances and clamp flags of every primitive of the copies -1, 0, +1, each evaluated
    in full by _segments / _arcs (angles and all): the reference for _distances."""
    from bristlecrawler.contact import profile as P

    c = P.profile_chain(gr.profile())
    m = jnp.floor((p[0] - c.x0) / c.period)
    dist, clamped = [], []
    for k in (-1.0, 0.0, 1.0):
        pk = p - jnp.array([(m + k) * c.period, 0.0])
        for part in (P._segments(c, pk), P._arcs(c, pk)):
            dist.append(part[0])
            clamped.append(part[1])
    return jnp.concatenate(dist), jnp.concatenate(clamped), P._distances(c, p, m)


@pytest.mark.slow
@given(gr=_groove_params(), x=st.floats(-5, 5), y=st.floats(-2, 1))
def test_ranking_distances_equal_the_full_evaluation(gr, x, y):
    """The winner is chosen from distances computed by a cone test (no angles): they equal
    those of the full evaluation of every segment and arc, and so do the clamp flags away
    from a cone's boundary (where they only move a rank by the 1e-9 mm clamp bias)."""
    dist, clamped, (fast, fast_clamped) = _full_ranking(gr, jnp.array([x, y]))
    np.testing.assert_allclose(fast, dist, rtol=0, atol=1e-12)
    differ = np.asarray(fast_clamped != clamped)
    # a differing flag is a round-off tie on a cone's boundary: the clamped and unclamped
    # closest points coincide there, so both evaluations give the same distance
    assert not differ.any() or np.allclose(np.asarray(fast)[differ], np.asarray(dist)[differ])


def _arc_length_gradient_cases():
    saw = st.tuples(st.floats(0.5, 3.0), st.floats(0.1, 1.0), st.floats(0.05, 0.95)).map(
        lambda t: Sawtooth(pitch=t[0], height=t[1], rise_fraction=t[2])
    )
    return st.one_of(_groove_params(), saw)


arc_length_one = jax.jit(lambda sub, p: project(sub, p).arc_length)
arc_length_grad = jax.jit(jax.grad(lambda sub, p: project(sub, p).arc_length, argnums=1))


@pytest.mark.slow
@given(sub=_arc_length_gradient_cases(), x=st.floats(-5, 5), y=st.floats(-2, 1))
def test_arc_gradient_is_the_derivative_of_the_arc_length(sub, x, y):
    """Projection.arc_gradient (closed form) equals autodiff of the arc length, and central
    differences where the arc length is smooth (forward and backward differences agree)."""
    p = jnp.array([x, y])
    pr = project_one(sub, p)
    np.testing.assert_allclose(pr.arc_gradient, arc_length_grad(sub, p), rtol=1e-12, atol=1e-12)
    h = 1e-6
    s0 = float(arc_length_one(sub, p))
    fwd = np.array([float(arc_length_one(sub, p + h * e)) - s0 for e in jnp.eye(2)]) / h
    bwd = np.array([s0 - float(arc_length_one(sub, p - h * e)) for e in jnp.eye(2)]) / h
    if np.allclose(fwd, bwd, atol=1e-4):
        np.testing.assert_allclose(pr.arc_gradient, 0.5 * (fwd + bwd), atol=1e-5)


def test_arc_gradient_on_a_fillet_is_tangent_times_radius_over_distance():
    """Above a convex land fillet of radius r, a point at distance rho from its centre moves
    its closest point by r / rho of its own tangential motion."""
    r = 0.2
    gr = Grooves(width=1.0, depth=0.5, pitch=2.0, fillet_top=r)
    # the land corner at x = 1 (right wall of groove 0): fillet centre (1 + r, -r)
    centre = np.array([1.0 + r, -r])
    direction = np.array([-1.0, 1.0]) / math.sqrt(2.0)
    for rho in (0.25, 0.4, 0.6):
        pr = project_one(gr, jnp.array(centre + rho * direction))
        assert float(pr.gap) == pytest.approx(rho - r, abs=1e-12)
        assert float(jnp.linalg.norm(pr.arc_gradient)) == pytest.approx(r / rho, rel=1e-12)
        assert float(jnp.dot(pr.arc_gradient, pr.tangent)) == pytest.approx(r / rho, rel=1e-12)


@given(
    phase=st.floats(0.0, 2.0),
    x0=st.floats(-50.0, 50.0),
    span=st.floats(0.1, 120.0),
)
def test_drawing_of_the_grooves_is_their_profile_over_the_whole_span(phase, x0, span):
    """The figures' polyline (periods of vertices, fillets left out) covers [x0, x0 + span]
    and lies at the groove floor inside a groove and on the land elsewhere."""
    from bristlecrawler.contact.profile import drawing

    g = Grooves(width=1.0, depth=0.25, pitch=2.0, phase=phase, fillet_top=0.02)
    d = drawing(g.profile(), x0, x0 + span)
    assert d[0, 0] <= x0 and d[-1, 0] >= x0 + span
    assert np.all(np.diff(d[:, 0]) >= 0)
    x = np.linspace(x0, x0 + span, 997)
    in_groove = np.mod(x - phase, 2.0) < 1.0
    off_wall = np.minimum(np.abs(np.mod(x - phase + 1e-3, 1.0)), 1.0) > 2e-3
    # y along the drawing at x (np.interp takes the value at the last of equal x)
    y = np.interp(x[off_wall], d[:, 0], d[:, 1])
    np.testing.assert_allclose(y, np.where(in_groove[off_wall], -0.25, 0.0), atol=1e-12)
