"""The corner term's tangent assembled from each pair's four outline points
(:func:`bristlecrawler.contact.corner_tangent.near_forces`) against the derivative through the
whole outline (``local_tangent=False``, plain autodiff of the same residual)."""

import dataclasses
import math

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from hypothesis import assume, example, given, settings
from hypothesis import strategies as st

from bristlecrawler import fe
from bristlecrawler.contact import CoulombLaw, Grooves
from bristlecrawler.contact.corner import FaceCornerContact, beam_outline
from bristlecrawler.contact.outline import select_feature

N_EL = 12
LENGTH = 6.0
THICK = 0.5


def _strip(law, y0=0.5 * THICK, clamped=False, local=True):
    """A strip 6 mm long and 0.5 mm thick along y = ``y0`` (its lower face on the land
    level by default), free or clamped at its left end, above grooves 1 mm wide every
    2 mm with land edges rounded to 0.02 mm: (structure, term, node positions (n, 2),
    term parameters)."""
    s = fe.Structure()
    a = s.node(0.0, y0)
    sec = fe.TaperedRect(E=1.0, b=1.0, h0=THICK, h1=THICK, rho=1e-9, nu=0.3)
    nodes = s.chain(a, (LENGTH, y0), N_EL, sec)
    if clamped:
        s.fix(a)
    outline, off = beam_outline(nodes, np.full(len(nodes), THICK), (0.0, 1.0))
    term = FaceCornerContact((outline,), 6, local_tangent=local)
    sub = Grooves(width=1.0, depth=0.25, pitch=2.0, phase=0.25, fillet_top=0.02)
    p = FaceCornerContact.params(np.asarray(s._X), (outline,), [off], sub, law)
    return s, term, np.asarray(s._X)[:, :2], p


def _placed(X, edge, offset, theta, depth, noise, rng, gaps=None):
    """Displacements (n, 3) turning the strip by ``theta`` about its tip and moving its
    lowest face point to ``offset`` mm right of the land edge at x = ``edge``, plus
    random bending of amplitude ``noise`` (mm; rotations noise / 0.3); then, given
    ``gaps(u)`` (every pair's gap), down until its deepest pair with the corners
    penetrates by ``depth`` mm."""
    c, s = math.cos(theta), math.sin(theta)
    tip = X[-1]
    x = (X - tip) @ np.array([[c, -s], [s, c]]).T + tip
    normal = 0.5 * THICK * np.array([-s, c])
    faces = np.concatenate([x + normal, x - normal])
    low = faces[np.argmin(faces[:, 1])]
    x += np.array([edge + offset, 0.0]) - low
    u = np.zeros((len(X), 3))
    u[:, :2] = x - X
    u[:, 2] = theta
    u += rng.uniform(-1.0, 1.0, u.shape) * noise * np.array([1.0, 1.0, 1.0 / 0.3])
    for _ in range(4 if gaps is not None else 0):  # the closest feature may change
        u[:, 1] -= float(jnp.min(gaps(jnp.asarray(u)))) + depth
    return jnp.asarray(u)


class _Programs:
    """The free strip, and compiled programs of its corner term taking the parameters as
    an argument (so that every law shares them): the residual and its dense Jacobian in
    u, for the local tangent (``loc``, the residual being the primal of a JVP, i.e. the
    custom rule's own value) and through the whole outline (``all``), fresh history,
    commit, every pair's gap, and the feature each pair projects on. ``freeze`` is
    static: False leaves the statuses out of the program (mode None), True freezes them."""

    def __init__(self):
        _, self.term, self.X, _ = _strip(LAW)
        term, whole = self.term, dataclasses.replace(self.term, local_tangent=False)

        def residual(t):
            def f(u, h, p, freeze):
                return t.residual(u, jnp.zeros_like(u), 0.0, h, p, freeze)

            return f

        f_loc, f_all = residual(term), residual(whole)

        def primal_of_jvp(u, h, p, freeze):
            return jax.jvp(lambda u: f_loc(u, h, p, freeze), (u,), (jnp.ones_like(u),))[0]

        static = {"static_argnums": 3}
        self.f_loc = jax.jit(primal_of_jvp, **static)
        self.f_all = jax.jit(f_all, **static)
        self.K_loc = jax.jit(jax.jacfwd(f_loc), **static)
        self.K_all = jax.jit(jax.jacfwd(f_all), **static)
        self.fresh = jax.jit(term.history_at)
        self.commit = jax.jit(term.commit)
        self.gaps = jax.jit(lambda u, p: term._gs(u, term._k0(u, p), p)[0])

        def features(u, h, p):
            C, _ = term._window(h.k0, p)
            P = term._points(u, p)[0]
            return jax.vmap(select_feature, in_axes=(None, None, 0))(P, p.side[0], C[0])

        self.features = jax.jit(features)
        self.current = jax.jit(lambda u, h, p: term._current(u, h.k0, h.anchor, p))

    def params(self, law):
        return _strip(law)[3]


LAW = CoulombLaw.for_reference_load(0.5, load=1.0)
_PROGRAMS = []


def _setup():
    if not _PROGRAMS:
        _PROGRAMS.append(_Programs())
    return _PROGRAMS[0]


@pytest.mark.slow
@settings(max_examples=10, deadline=None)
@given(
    edge=st.sampled_from([6.25, 7.25]),
    offset=st.floats(-0.05, 0.05),
    theta=st.floats(-0.8, 0.1),
    depth=st.floats(2e-4, 3e-3),
    slip=st.floats(0.0, 3.0),
    freeze=st.booleans(),
    seed=st.integers(0, 2**31 - 1),
)
@example(edge=7.25, offset=-0.01, theta=0.02, depth=2e-3, slip=1.0, freeze=False, seed=1)
@example(edge=6.25, offset=0.01, theta=-0.03, depth=3e-3, slip=2.0, freeze=True, seed=2)
@example(edge=7.25, offset=0.0, theta=0.0, depth=2e-3, slip=0.5, freeze=False, seed=3)
def test_local_tangent_equals_the_whole_outline_derivative(
    edge, offset, theta, depth, slip, freeze, seed
):
    """Strips pressed onto the rounded land edges at random places and tilts (a tip
    corner, the end face or the lower face on an edge), bent a little, with stick
    anchors moved at random by up to ``slip`` times the elastic slip limit (pairs in
    stick and in slip, both directions), with and without frozen statuses (stick): the
    residuals are the same, and the local tangent is the derivative through the whole
    outline to round-off."""
    pr = _setup()
    u, h, p = _state(pr, edge, offset, theta, depth, slip, seed)
    touches = _check_state(pr, u, h, p, freeze)
    assume(touches)  # something touches (not where the closest feature jumps)


def _state(pr, edge, offset, theta, depth, slip, seed):
    """(u, history, params) of a strip placed by :func:`_placed`, its stick anchors moved
    by up to ``slip`` times the elastic slip limit, the committed statuses those of the
    unmoved anchors (closed pairs stick: frozen, they differ from the return mapping's
    where the moved anchors put a pair in slip)."""
    p = pr.params(LAW)
    rng = np.random.default_rng(seed)
    u = _placed(pr.X, edge, offset, theta, depth, 0.05 * depth, rng, lambda u: pr.gaps(u, p))
    h = pr.fresh(u, p)
    state = pr.commit(u, u, 0.0, h, p).state
    limit = float(LAW.mu * LAW.k_n * depth / LAW.k_t)
    moved = h.anchor + rng.uniform(-slip, slip, h.anchor.shape) * limit
    return u, dataclasses.replace(h, anchor=moved, state=state), p


def _check_state(pr, u, h, p, freeze) -> bool:
    """The local path's residual (the JVP rule's primal) is the whole outline's bit for
    bit and its tangent the whole outline's to 1e-10 of the largest entry; returns
    whether any pair is closed."""
    r_loc, r_all = np.asarray(pr.f_loc(u, h, p, freeze)), np.asarray(pr.f_all(u, h, p, freeze))
    np.testing.assert_array_equal(r_loc, r_all)
    Kl, Ka = np.asarray(pr.K_loc(u, h, p, freeze)), np.asarray(pr.K_all(u, h, p, freeze))
    np.testing.assert_allclose(Kl, Ka, rtol=0, atol=1e-10 * np.abs(Ka).max())
    return bool(np.abs(r_all).max() > 0)


@pytest.mark.slow
def test_local_tangent_on_thirty_states_covers_every_feature_and_status():
    """The same check on 30 seeded states, and what they cover: closed pairs on a face
    segment and on a sharp vertex of the tip, in stick and in slip of both signs, with the
    return mapping's statuses and with frozen ones."""
    from bristlecrawler.contact.coulomb import return_map

    pr = _setup()
    rng = np.random.default_rng(0)
    seen = set()
    for trial in range(30):
        u, h, p = _state(
            pr,
            (6.25, 7.25)[trial % 2],
            rng.uniform(-0.05, 0.05),
            rng.uniform(-0.8, 0.1),
            rng.uniform(2e-4, 3e-3),
            rng.uniform(0.0, 3.0),
            trial,
        )
        freeze = trial % 3 == 0
        if not _check_state(pr, u, h, p, freeze):
            continue
        cur = pr.current(u, h, p)
        step = return_map(*cur, LAW)
        _, _, _, found, seg_wins, _ = (np.asarray(x) for x in pr.features(u, h, p))
        for j in np.flatnonzero(np.asarray(step.p_n)[0] > 0):
            feature = "segment" if seg_wins[j] else "vertex" if found[j] else "far"
            delta = float(cur[1][0, j] - cur[2][0, j])
            status = int(np.asarray(step.state)[0, j])
            seen.add((feature, status, np.sign(delta) if status == 2 else 0, freeze))
    features = {f for f, *_ in seen}
    assert {"segment", "vertex"} <= features
    assert {(st_, sg) for _, st_, sg, _ in seen} >= {(1, 0), (2, 1.0), (2, -1.0)}
    assert {fr for *_, fr in seen} == {True, False}


@pytest.mark.slow
def test_local_tangent_lacks_the_stretch_of_segments_beyond_its_window():
    """The documented limit: a pair whose stick anchor lies more than a segment away from
    its closest point (possible only with a stick band wider than a segment: here k_t is
    so soft that a 1.2 mm elastic slip sticks) pulls on the segments in between; the
    residual still has that force, the local tangent lacks its derivative, a stiffness
    of the order of k_t."""
    soft = CoulombLaw(mu=0.5, k_n=1000.0, k_t=0.5)
    pr = _setup()
    p = pr.params(soft)
    u = _placed(pr.X, 7.5, 0.0, 0.0, 2e-3, 0.0, np.random.default_rng(0), lambda u: pr.gaps(u, p))
    h = pr.fresh(u, p)
    # 2.4 segments of 0.5 mm back: beyond the segment before the closest point's
    h = dataclasses.replace(h, anchor=h.anchor - 1.2)
    h = dataclasses.replace(h, state=pr.commit(u, u, 0.0, h, p).state)
    assert np.any(np.asarray(h.state) == 1)  # in stick
    np.testing.assert_array_equal(
        np.asarray(pr.f_loc(u, h, p, False)), np.asarray(pr.f_all(u, h, p, False))
    )
    Kl, Ka = np.asarray(pr.K_loc(u, h, p, False)), np.asarray(pr.K_all(u, h, p, False))
    assert np.abs(Kl - Ka).max() > 0.1 * float(soft.k_t)


@pytest.mark.slow
def test_derivative_in_the_parameters_is_the_whole_outlines():
    """A tangent in anything but the displacements (here the friction coefficient and the
    corner positions) takes the derivative through the whole outline."""
    pr = _setup()
    p, term = pr.params(LAW), pr.term
    u = _placed(pr.X, 6.2, 0.0, 0.01, 2e-3, 1e-4, np.random.default_rng(4), lambda u: pr.gaps(u, p))
    h = pr.fresh(u, p)
    h = dataclasses.replace(h, anchor=h.anchor + 1e-4)
    whole = dataclasses.replace(term, local_tangent=False)

    def seed(leaf):
        seeded = leaf is p.corners or leaf is p.law.mu
        return jnp.ones_like(leaf) if seeded else jnp.zeros_like(leaf)

    dp = jax.tree_util.tree_map(seed, p)
    assert float(dp.law.mu) == 1.0 and float(jnp.min(dp.corners)) == 1.0
    du = jnp.asarray(np.random.default_rng(5).normal(size=u.shape))

    def jvp(t):
        return jax.jit(
            lambda u, p: jax.jvp(lambda u, p: t.residual(u, u * 0, 0.0, h, p), (u, p), (du, dp))[1]
        )(u, p)

    a, b = np.asarray(jvp(term)), np.asarray(jvp(whole))
    assert np.abs(b).max() > 0
    np.testing.assert_allclose(a, b, rtol=0, atol=1e-10 * np.abs(b).max())


@pytest.mark.slow
def test_banded_newton_tangent_equals_the_whole_outline_jacobian():
    """Through the solver's coloured extraction (the products of the Newton tangent) the
    local tangent of a clamped strip pressed onto the land edges gives the dense
    Jacobian of the residual differentiated through the whole outline."""
    from bristlecrawler.fe import assembly, banded

    rng = np.random.default_rng(7)
    fns = []
    for local in (True, False):
        st_, term, _, tp = _strip(LAW, 0.5 * THICK - 2e-3, clamped=True, local=local)
        st_.add_term(term, tp)
        m = st_.build()
        topo, p = m.topology, m.params
        if not fns:
            u = rng.uniform(-1.0, 1.0, (topo.n_nodes, 3)) * np.array([3e-4, 3e-4, 1e-3])
            u = jnp.asarray(u).at[0].set(0.0)
            h = term.history_at(u, p.extra[0])
            h = dataclasses.replace(h, anchor=h.anchor + rng.uniform(-3e-4, 3e-4, h.anchor.shape))
            corner = term.residual(u, jnp.zeros_like(u), 0.0, h, p.extra[0])
            assert np.abs(np.asarray(corner)).max() > 0  # the strip touches land edges
            q = u[np.array([n for n, _ in topo.red]), np.array([d for _, d in topo.red])]

        def fn(q, m=m, topo=topo, p=p, h=h):
            full = assembly.expand(q, 0.0, 1.0, p, topo)
            f = assembly.terms_residual(full, jnp.zeros_like(full), 0.0, (h,), p, m.terms)
            return jax.vjp(lambda q: assembly.expand(q, 0.0, 1.0, p, topo), q)[1](f)[0]

        fns.append((fn, topo))
    (fn_loc, topo), (fn_all, _) = fns
    dense = np.asarray(jax.jit(jax.jacfwd(fn_all))(q))
    n = len(q)
    system = jax.jit(lambda q: banded.extract(fn_loc, q, topo)[1])(q)
    band = banded.to_scipy(system, topo).toarray()[:n, :n]
    assert np.abs(dense).max() > 0
    np.testing.assert_allclose(band, dense, rtol=0, atol=1e-9 * np.abs(dense).max())
