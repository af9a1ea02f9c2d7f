"""Corner-to-face contact (substrate corners against beam faces): geometry and a statics
case with a closed form."""

import dataclasses
import math

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from bristlecrawler import fe
from bristlecrawler.contact import CoulombLaw, Grooves
from bristlecrawler.contact.corner import (
    FaceCornerContact,
    beam_outline,
    convex_corners,
)
from bristlecrawler.contact.outline import clearance, pair_gap


def test_convex_corners_of_grooves_are_the_land_edges():
    g = Grooves(width=1.0, depth=0.25, pitch=2.0, phase=0.3, fillet_top=0.1)
    c, r, period = convex_corners(g)
    assert period == pytest.approx(2.0)
    np.testing.assert_allclose(r, [0.1, 0.1])
    # fillet centres one radius inside the land, below its top
    xs = np.sort(np.mod(c[:, 0] - 0.3, 2.0))
    np.testing.assert_allclose(xs, [1.0 + 0.1, 2.0 - 0.1])
    np.testing.assert_allclose(c[:, 1], -0.1)


def _outline(axis, nrm):
    """Closed outline 0.5 mm thick about ``axis`` points (k, 2) with normals ``nrm``:
    points, reference arc and orientation side."""
    P = np.concatenate([axis + 0.25 * nrm, axis[::-1] - 0.25 * nrm, axis[:1] + 0.25 * nrm])
    seg = np.diff(P, axis=0)
    arc = np.concatenate([[0.0], np.cumsum(np.hypot(seg[:, 0], seg[:, 1]))])
    area = 0.5 * np.sum(P[:-1, 0] * P[1:, 1] - P[1:, 0] * P[:-1, 1])
    return P, arc, np.sign(area)


def _strip(angle, side):
    """Closed outline of a straight strip 3 mm long, 0.5 mm thick, axis through (0.3,
    -0.2) along ``angle``; the 'face' is the one on the ``side`` of the axis."""
    e = np.array([math.cos(angle), math.sin(angle)])
    nrm = side * np.array([-e[1], e[0]])
    axis = np.array([k * 0.75 * e for k in range(5)]) + np.array([0.3, -0.2])
    return (*_outline(axis, nrm), axis, e, nrm)


@pytest.mark.slow
@settings(max_examples=60, deadline=None)
@given(
    angle=st.floats(-math.pi, math.pi),
    t=st.floats(0.02, 0.98),
    d=st.floats(-0.2, 2.0),
    rho=st.floats(0.0, 0.1),
    side=st.sampled_from([-1.0, 1.0]),
)
# On the normal line of a vertex (t = 0.5 is the middle vertex of the face): round-off put
# the fan parameter just outside both adjacent segments and the opposite face won.
@example(angle=0.3148310739268325, t=0.5, d=1.121972924947381, rho=0.0, side=-1.0)
def test_gap_to_a_straight_face_is_the_distance_to_its_line(angle, t, d, rho, side):
    """A corner beside a straight face at signed distance d from it along its outward
    normal (inside the strip for d < 0, less than half the thickness): gap = d - rho (or
    minus the distance to an end face when that is nearer), arc
    coordinate = reference arc length along the face, up to the end faces (sharp corners
    are not smoothed)."""
    P, arc, orient, axis, e, nrm = _strip(angle, side)
    C = axis[0] + 0.25 * nrm + t * 3.0 * e + d * nrm
    g, s = pair_gap(jnp.asarray(P), jnp.asarray(arc), orient, jnp.asarray(C), rho)
    to_end = 3.0 * min(t, 1.0 - t)  # inside, an end face may be the nearer boundary
    if d >= 0 or -d < to_end:
        assert float(g) == pytest.approx(d - rho, abs=1e-12)
        assert float(s) == pytest.approx(3.0 * t, abs=1e-12)
    else:
        assert float(g) == pytest.approx(-to_end - rho, abs=1e-12)


@pytest.mark.slow
@settings(max_examples=60, deadline=None)
@given(angle=st.floats(-math.pi, math.pi), r=st.floats(0.01, 2.0), phi=st.floats(-1.5, 1.5))
def test_corner_beyond_the_end_of_a_strip_is_outside(angle, r, phi):
    """Beyond the end face the gap is positive, and straight ahead of the end face's middle
    it is the distance to the end face."""
    P, arc, orient, axis, e, nrm = _strip(angle, 1.0)
    for direction, exact in ((math.cos(phi) * e + math.sin(phi) * nrm, False), (e, True)):
        C = axis[-1] + r * direction
        g, _ = pair_gap(jnp.asarray(P), jnp.asarray(arc), orient, jnp.asarray(C), 0.0)
        assert float(g) > 0
        if exact:
            assert float(g) == pytest.approx(r, abs=1e-12)


def _bent_strip():
    """Closed outline of a bent strip 0.5 mm thick (upper face concave) over 9 axis points:
    points P, reference arc, orientation side, and the axis normals (9, 2). As built, the
    -n face takes the normals in axis order (not reversed) and the closing stretch has a
    point per axis normal: the tests use the +n face only."""
    x = np.linspace(0.0, 4.0, 9)
    axis = np.stack([x, 0.15 * (x - 2.0) ** 2], axis=1)
    tang = np.gradient(axis, axis=0)
    tang /= np.linalg.norm(tang, axis=1)[:, None]
    nrm = np.stack([-tang[:, 1], tang[:, 0]], axis=1)
    return (*_outline(axis, nrm), nrm)


@pytest.mark.slow
def test_gap_and_arc_are_continuous_around_a_bent_outline():
    """A corner moved along a path past the vertices of a bent (kinked) strip, in contact
    depth: gap and arc coordinate change by at most a few times the path step between
    samples (no jumps at the vertices, on the concave side included)."""
    P, arc, side, _ = _bent_strip()
    xs = np.linspace(0.6, 3.4, 2001)
    pairs = jax.jit(jax.vmap(pair_gap, in_axes=(None, None, None, 0, None)))
    # inside, on, outside the concave upper face (a plain closest-point projection would
    # jump in s by ~ depth x kink angle = 0.1 x 0.15 mm at every vertex here)
    for depth in (-0.1, 0.0, 0.1):
        ys = 0.15 * (xs - 2.0) ** 2 + 0.25 + depth
        g, s = (
            np.asarray(v)
            for v in pairs(jnp.asarray(P), jnp.asarray(arc), side, jnp.stack([xs, ys], axis=1), 0.0)
        )
        step = np.hypot(np.diff(xs), np.diff(ys)).max()
        assert np.abs(np.diff(g)).max() < 0.2 * step
        assert np.abs(np.diff(s)).max() < 3.0 * step
        assert np.all(np.diff(s) > 0)


@pytest.mark.slow
@pytest.mark.parametrize("depth", [-0.01, -1e-4])
def test_gap_gradient_is_continuous_across_an_outline_vertex(depth):
    """The gap's derivative with respect to the outline points (the normal force's
    distribution on the nodes) and to the corner (its direction on the corner) is the
    same on both sides of a vertex of a bent face, up to terms of the order of the step.
    With the fan parameter t differentiated, dg/dt = -AB . n(t) added a force along the
    face of about (half the vertex's turn) x p_N, with opposite signs on the two sides."""
    P, arc, side, nrm = _bent_strip()
    arc = jnp.asarray(arc)
    grad = jax.jit(jax.grad(lambda P, C: pair_gap(P, arc, side, C, 0.0)[0], argnums=(0, 1)))
    jumps = []
    for v in (2, 3, 6):  # smooth vertices of the upper (+n) face, turns of 8-17 degrees
        n_v = nrm[v] / np.linalg.norm(nrm[v])
        t_v = np.array([n_v[1], -n_v[0]])
        C0 = P[v] + depth * n_v  # on the vertex's normal line, inside by |depth|
        sides = [grad(jnp.asarray(P), jnp.asarray(C0 + e * t_v)) for e in (-1e-7, 1e-7)]
        gP = [np.asarray(g[0]) for g in sides]
        gC = [np.asarray(g[1]) for g in sides]
        jumps.append(max(np.abs(gP[0] - gP[1]).max(), np.abs(gC[0] - gC[1]).max()))
        np.testing.assert_allclose(gC[0], n_v, atol=2e-3)  # along the vertex normal
    assert max(jumps) < 1e-5


def _propped_cantilever(n_el, a, P, law_load):
    """Horizontal cantilever (clamp at x = 0) whose lower face rests on the right edge of a
    1 mm land at x = a; tip load P downwards. Only corner contact, frictionless."""
    E, b, h, L = 1000.0, 1.0, 0.5, 10.0
    s = fe.Structure()
    clamp = s.node(0.0, 0.5 * h)
    sec = fe.TaperedRect(E=E, b=b, h0=h, h1=h, rho=1e-9, nu=0.3, shear=False)
    nodes = s.chain(clamp, (L, 0.5 * h), n_el, sec)
    s.fix(clamp)
    s.load(nodes[-1], fy=-P)
    sub = Grooves(width=19.0, depth=0.25, pitch=20.0, phase=a - 20.0)  # land [a - 1, a]
    law = CoulombLaw.for_reference_load(0.0, load=law_load)
    outline, off = beam_outline(nodes, np.full(len(nodes), h), (0.0, 1.0))
    term = FaceCornerContact((outline,), FaceCornerContact.window_periods(L, 20.0, 1.0))
    X = np.asarray(s._X)
    s.add_term(term, FaceCornerContact.params(X, (outline,), [off], sub, law))
    m = s.build()
    res = fe.solve_static(m, check_support=False)
    assert res.ok, res.message
    g, _ = term._gs(res.state.u, res.state.history[0].k0, m.params.extra[0])
    reactions = np.maximum(-float(law.k_n) * np.asarray(g), 0.0)
    EI = E * b * h**3 / 12.0
    return reactions, float(law.k_n), EI, L


@pytest.mark.slow
@pytest.mark.parametrize("a", [7.0, 5.0])
def test_propped_cantilever_reaction_matches_the_closed_form(a):
    """Euler-Bernoulli, small deflection: an end load P on a cantilever propped at x = a by
    a support of stiffness k_n (the penalty) gets the prop reaction
    R = P (3L - a) / (2a) / (1 + 3 EI / (k_n a^3)). The land's other edge (x = a - 1) stays
    open because the beam rises there. Exact for the Hermite beam with the prop at a node."""
    P = 1e-3
    reactions, k_n, EI, L = _propped_cantilever(20, a, P, law_load=1.0)
    R = P * (3 * L - a) / (2 * a) / (1.0 + 3.0 * EI / (k_n * a**3))
    assert np.count_nonzero(reactions) == 1
    assert reactions.max() == pytest.approx(R, rel=2e-4)


@pytest.mark.slow
def test_window_follows_a_face_and_carries_its_pairs():
    """Commit after moving a face by one period: the window re-centres by one period and
    every corner that stays in it keeps its pair (anchor, state, forces from the return
    mapping of that same corner), new slots start open, dissipation is kept."""
    from bristlecrawler.contact.coulomb import return_map

    s = fe.Structure()
    a = s.node(0.0, 0.25 - 1e-4)  # lower face 0.1 micrometre into the lands
    nodes = s.chain(
        a, (4.0, 0.25 - 1e-4), 4, fe.TaperedRect(E=1.0, b=1.0, h0=0.5, h1=0.5, rho=1e-9, nu=0.3)
    )
    outline, off = beam_outline(nodes, np.full(5, 0.5), (0.0, 1.0))
    term = FaceCornerContact((outline,), 4)
    sub = Grooves(width=1.0, depth=0.25, pitch=2.0)
    law = CoulombLaw.for_reference_load(0.5, load=1.0)
    p = FaceCornerContact.params(np.asarray(s._X), (outline,), [off], sub, law)
    u0 = jnp.zeros((5, 3))
    h0 = term.history_at(u0, p)
    h0 = dataclasses.replace(h0, dissipation=h0.dissipation + 0.25)
    u1 = u0.at[:, 0].set(2.0)
    h1 = term.commit(u1, u0, 0.0, h0, p)
    assert int(h1.k0[0]) == int(h0.k0[0]) + 1
    g_old, s_old = term._gs(u1, h0.k0, p)
    ref = return_map(g_old, s_old, h0.anchor, law)
    k = 2  # corners per period: new slot i is old slot i + 2
    assert np.any(np.asarray(ref.state)[0, k:] != 0)  # some carried pairs are closed
    np.testing.assert_allclose(np.asarray(h1.anchor)[0, :-k], np.asarray(ref.anchor)[0, k:])
    np.testing.assert_array_equal(np.asarray(h1.state)[0, :-k], np.asarray(ref.state)[0, k:])
    assert np.all(np.asarray(h1.state)[0, -k:] == 0)
    total = float(jnp.sum(h0.dissipation) + jnp.sum(ref.dissipation))
    assert float(jnp.sum(h1.dissipation)) == pytest.approx(total, rel=1e-12)


class _Undeclared(FaceCornerContact):
    """The corner term without its coupling declaration (what the solver saw before)."""

    def couplings(self):
        return ()


def _pressed_strip(term_cls, n_el=12):
    """A 6 mm strip lying 2 micrometres deep on the lands of 1 mm grooves (several corners
    in contact, mu = 0.5), clamped at its left end: model, term, displacement, history."""
    s = fe.Structure()
    a = s.node(0.0, 0.25 - 2e-3)
    sec = fe.TaperedRect(E=1.0, b=1.0, h0=0.5, h1=0.5, rho=1e-9, nu=0.3)
    nodes = s.chain(a, (6.0, 0.25 - 2e-3), n_el, sec)
    s.fix(a)
    outline, off = beam_outline(nodes, np.full(len(nodes), 0.5), (0.0, 1.0))
    term = term_cls((outline,), 6)
    law = CoulombLaw.for_reference_load(0.5, load=1.0)
    sub = Grooves(width=1.0, depth=0.25, pitch=2.0, phase=0.25)
    s.add_term(term, FaceCornerContact.params(np.asarray(s._X), (outline,), [off], sub, law))
    m = s.build()
    rng = np.random.default_rng(3)
    u = jnp.zeros((m.topology.n_nodes, 3))
    h = term.history_at(u, m.params.extra[0])
    # bend the strip a little (rotations up to 1 mrad, displacements up to 0.3 um):
    # every pair reads four outline points that move differently
    du = rng.uniform(-1.0, 1.0, (m.topology.n_nodes, 3)) * np.array([3e-4, 3e-4, 1e-3])
    return m, term, u + jnp.asarray(du).at[0].set(0.0), h


def _tangents(m, u, h):
    from bristlecrawler.fe import assembly, banded

    topo, p = m.topology, m.params
    q = jnp.asarray(u)[np.array([n for n, _ in topo.red]), np.array([d for _, d in topo.red])]

    def fn(q):
        full = assembly.expand(q, 0.0, 1.0, p, topo)
        f = assembly.terms_residual(full, jnp.zeros_like(full), 0.0, (h,), p, m.terms)
        return jax.vjp(lambda q: assembly.expand(q, 0.0, 1.0, p, topo), q)[1](f)[0]

    dense = np.asarray(jax.jit(jax.jacfwd(fn))(q))
    n = len(q)
    band = jax.jit(lambda q: banded.extract(fn, q, topo)[1])(q)
    banded_J = banded.to_scipy(band, topo).toarray()[:n, :n]
    return dense, banded_J


@pytest.mark.slow
def test_banded_tangent_keeps_every_coupling_of_the_corner_term():
    """The corner term reads four consecutive outline points per pair (nodes up to three
    apart); it declares them, the structure widens its band, and the coloured-JVP tangent
    equals the dense Jacobian. Without the declaration (the solver before this fix) the
    couplings outside the chain's band are lost, which made Newton converge linearly."""
    m, term, u, h = _pressed_strip(FaceCornerContact)
    stuck = term.commit(u, u, 0.0, h, m.params.extra[0])
    assert np.count_nonzero(np.asarray(stuck.state) == 1) >= 3  # several pairs in stick
    dense, band = _tangents(m, u, h)
    assert np.abs(dense).max() > 0
    np.testing.assert_allclose(band, dense, rtol=0, atol=1e-9 * np.abs(dense).max())

    m0, _, u0, h0 = _pressed_strip(_Undeclared)
    assert m0.topology.bs < m.topology.bs
    dense0, band0 = _tangents(m0, u0, h0)
    np.testing.assert_allclose(dense0, dense, rtol=1e-12, atol=1e-12)  # same physics
    assert np.abs(band0 - dense0).max() > 1e-3 * np.abs(dense0).max()


def _residual_and_tangent(term, p, u, h):
    """The corner term's force on the nodes (n_nodes, 3) and its dense Jacobian in u."""

    def f(u):
        return term.residual(u, jnp.zeros_like(u), 0.0, h, p)

    return np.asarray(jax.jit(f)(u)), np.asarray(jax.jit(jax.jacfwd(f))(u))


@pytest.mark.slow
def test_tangent_through_the_closest_pairs_only_is_exact_while_they_hold_every_contact():
    """The corner term differentiates only the ``tangent_pairs`` pairs of an outline with
    the smallest clearances (lower bounds on the gaps). The residual is always that of
    every pair (with fewer tangent pairs than closed ones, the broad phase's fallback
    adds the others); the tangent is the full one while no other pair is closed, and
    only then."""
    m, term, u, h = _pressed_strip(FaceCornerContact)
    p = m.params.extra[0]
    closed = int(np.sum(np.asarray(term.commit(u, u, 0.0, h, p).p_n) > 0))
    assert 2 <= closed < 2 * term.periods  # two land edges per period
    every = dataclasses.replace(term, tangent_pairs=2 * term.periods)
    res_full, dense_full = _residual_and_tangent(every, p, u, h)
    scale = np.abs(dense_full).max()
    for k, exact in ((closed, True), (closed - 1, False)):
        res, dense = _residual_and_tangent(dataclasses.replace(term, tangent_pairs=k), p, u, h)
        np.testing.assert_allclose(res, res_full, rtol=1e-12, atol=1e-12)
        gap = np.abs(dense - dense_full).max()
        assert (gap <= 1e-9 * scale) if exact else (gap > 1e-3 * scale)


def test_a_term_coupling_a_missing_node_is_rejected():
    from bristlecrawler.errors import InputError

    s = fe.Structure()
    a = s.node(0.0, 0.0)
    s.chain(a, (1.0, 0.0), 2, fe.TaperedRect(E=1.0, b=1.0, h0=0.1, h1=0.1, rho=1e-9, nu=0.3))
    s.fix(a)
    term = FaceCornerContact(((0, 1, 2, 7, 0),), 1)
    s.add_term(term, ())
    with pytest.raises(InputError, match="node 7"):
        s.build()


@pytest.mark.slow
@pytest.mark.parametrize("stretch", [1.0, 1.2, 0.85])
def test_sliding_friction_is_coulomb_on_a_stretched_face(stretch):
    """A strip pressed 0.1 um into the land edges, stretched by ``stretch`` and slid
    0.3 mm to the right: every pair slips, and the total friction force is mu times the
    total normal force whatever the stretch (slip measured in current length; in
    reference arc length it was mu p_N / stretch). Every material point moves right by at
    least 0.3 mm, so all pairs slide the same way."""
    s = fe.Structure()
    a = s.node(0.0, 0.25 - 1e-4)
    nodes = s.chain(
        a, (4.0, 0.25 - 1e-4), 8, fe.TaperedRect(E=1.0, b=1.0, h0=0.5, h1=0.5, rho=1e-9, nu=0.3)
    )
    outline, off = beam_outline(nodes, np.full(9, 0.5), (0.0, 1.0))
    term = FaceCornerContact((outline,), 4)
    sub = Grooves(width=1.0, depth=0.25, pitch=2.0, phase=0.5)
    mu = 0.5
    law = CoulombLaw.for_reference_load(mu, load=1.0)
    X = np.asarray(s._X)
    p = FaceCornerContact.params(X, (outline,), [off], sub, law)
    u0 = jnp.zeros((9, 3))
    h0 = term.history_at(u0, p)
    shift = 0.3 + 4.0 * max(0.0, 1.0 - stretch)  # every material point moves right >= 0.3
    u1 = u0.at[:, 0].set(jnp.asarray((stretch - 1.0) * X[:, 0] + shift))
    R = np.asarray(term.residual(u1, u0, 0.0, h0, p))
    fx, fy = R[:, 0].sum(), R[:, 1].sum()
    assert fy < 0.0  # the corners push the strip up: residual = -force on it
    assert abs(fx) == pytest.approx(mu * abs(fy), rel=1e-9)
    h1 = term.commit(u1, u0, 0.0, h0, p)
    closed = np.asarray(h1.state)[0] > 0
    assert closed.sum() >= 2 and np.all(np.asarray(h1.state)[0][closed] == 2)  # all slip


@pytest.mark.slow
@settings(max_examples=40, deadline=None)
@given(
    angle=st.floats(-math.pi, math.pi),
    bend=st.floats(-0.3, 0.3),
    rho=st.floats(0.0, 0.1),
    seed=st.integers(0, 2**31 - 1),
)
def test_clearance_is_a_lower_bound_on_the_gap(angle, bend, rho, seed):
    """The corner term's broad phase: outside a beam outline (a strip 0.5 mm thick and 4
    mm long, bent with curvature ``2 bend`` and turned by ``angle``) the clearance,
    distance minus rho, never exceeds the gap of :func:`pair_gap`, so a pair with positive
    clearance is open; inside it is -inf and the pair is closed. Corners sampled inside,
    around and beyond the ends of the strip."""
    x = np.linspace(0.0, 4.0, 9)
    axis = np.stack([x, bend * (x - 2.0) ** 2], axis=1)
    tang = np.gradient(axis, axis=0)
    tang /= np.linalg.norm(tang, axis=1)[:, None]
    nrm = np.stack([-tang[:, 1], tang[:, 0]], axis=1)
    P = np.concatenate([axis + 0.25 * nrm, (axis - 0.25 * nrm)[::-1], axis[:1] + 0.25 * nrm[:1]])
    c, s_ = math.cos(angle), math.sin(angle)
    P = P @ np.array([[c, -s_], [s_, c]]).T
    seg = np.diff(P, axis=0)
    arc = np.concatenate([[0.0], np.cumsum(np.hypot(seg[:, 0], seg[:, 1]))])
    side = np.sign(np.sum(P[:-1, 0] * P[1:, 1] - P[1:, 0] * P[:-1, 1]))
    rng = np.random.default_rng(seed)
    C = jnp.asarray(rng.uniform(P.min(axis=0) - 1.0, P.max(axis=0) + 1.0, (400, 2)))
    g, _ = jax.vmap(pair_gap, in_axes=(None, None, None, 0, None))(
        jnp.asarray(P), jnp.asarray(arc), side, C, rho
    )
    lb = np.asarray(clearance(jnp.asarray(P), C, jnp.full(400, rho)))
    g = np.asarray(g)
    inside = np.isneginf(lb)
    assert 0 < inside.sum() < 400  # both kinds sampled
    assert np.all(g[inside] < -rho + 1e-12)
    assert np.all(lb[~inside] <= g[~inside] + 1e-12)
    assert np.all(g[lb > 0] > 0)
