"""Two tapered bristles clamped at 45 deg to an actuated body, on a toy penalty floor.

Checks the extension contract for contact (an extra residual term with history), the
bordered banded tangent against a dense autodiff Jacobian, gravity statics (vertical force
balance) and HHT dynamics that follows the actuated body length.
"""

import dataclasses
import math

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from bristlecrawler import fe
from bristlecrawler.fe import (
    Integrator,
    banded,
    initial_state,
    solve_static,
)
from bristlecrawler.fe.static import static_residual
from bristlecrawler.fe.terms import Term
from bristlecrawler.verification.structures import two_bristle_crawler


@dataclasses.dataclass(frozen=True)
class PenaltyFloor(Term):
    """Toy contact: penalty floor y >= y0 at ``nodes`` with a Coulomb-limited tangential
    spring to a stick anchor (history), return-mapped at commit. params = (kn N/mm,
    kt N/mm, mu, y0 mm)."""

    nodes: tuple

    def _forces(self, u, history, params, X):
        kn, kt, mu, y0 = params
        idx = np.asarray(self.nodes)
        pos = X[idx] + u[idx, :2]
        gap = pos[:, 1] - y0
        fn = kn * jnp.minimum(gap, 0.0)  # internal-force sign: negative pushes up
        trial = kt * (pos[:, 0] - history) * (gap < 0.0)
        limit = mu * jnp.abs(fn)
        ft = jnp.clip(trial, -limit, limit)
        return idx, fn, ft, pos

    def residual(self, u, v, t, history, params):
        X, p = params
        idx, fn, ft, _ = self._forces(u, history, p, X)
        return jnp.zeros_like(u).at[idx, 0].add(ft).at[idx, 1].add(fn)

    def init_history(self, topology, params):
        X, _ = params
        return X[np.asarray(self.nodes), 0]

    def commit(self, u, v, t, history, params):
        X, p = params
        kt = p[1]
        _, _, ft, pos = self._forces(u, history, p, X)
        return pos[:, 0] - ft / kt


def crawler(n=4):
    s, nodes = two_bristle_crawler(n)
    tips = tuple(c[-1] for c in nodes["chains"])
    # Floor 0.01 mm above the unloaded tips: in contact from the start (else the weightless
    # start is a free body and its tangent singular).
    y_tip = -5.0 - 5.0 * math.cos(math.pi / 4) + 0.01
    term = PenaltyFloor(tips)
    # The term needs reference positions: build once, then attach them as its params.
    m0 = s.build()
    params = (m0.params.X, jnp.asarray([50.0, 50.0, 0.65, y_tip]))
    s.add_term(term, params)
    return s.build(), nodes


@pytest.fixture(scope="module")
def model():
    return crawler()


@pytest.fixture(scope="module")
def equilibrium(model):
    """Gravity equilibrium on the floor (one static solve shared by the tests)."""
    m, _ = model
    res = solve_static(m)
    assert res.ok
    return res.state


def test_topology_is_bordered(model):
    m, _ = model
    topo = m.topology
    assert topo.n_border == 3  # the body (x, y, theta) couples both chains
    assert topo.bs <= 6


@pytest.mark.slow
def test_banded_jacobian_matches_dense(model):
    m, _ = model
    topo = m.topology
    rng = np.random.default_rng(1)
    q = jnp.asarray(rng.normal(scale=0.05, size=topo.n_red))
    hist = tuple(t.init_history(topo, p) for t, p in zip(m.terms, m.params.extra, strict=True))

    def f(q):
        return static_residual(q, 3.0, 1.0, hist, m.params, topo, m.terms)[0]

    dense = np.asarray(jax.jit(jax.jacfwd(f))(q))
    _, blocks = jax.jit(lambda q: banded.extract(f, q, topo))(q)
    sparse = banded.to_scipy(blocks, topo).toarray()
    assert np.allclose(sparse, dense, rtol=1e-12, atol=1e-12 * np.abs(dense).max())
    # The solve, on a shifted (nonsingular) version: at a random q the tips may be off the
    # floor, and then the free body makes J singular. J + shift I is the extracted system
    # with shift added on the diagonal blocks and the border block D (what extracting
    # f(q) + shift q gives; the padding rows only see a zero right-hand side), so only the
    # solve is compiled here, not a second residual.
    shift = float(np.abs(dense).max())
    r = jnp.asarray(rng.normal(size=topo.n_red))
    shifted = dataclasses.replace(
        blocks,
        diag=blocks.diag + shift * jnp.eye(topo.bs),
        D=blocks.D + shift * jnp.eye(topo.n_border),
    )
    x = np.asarray(jax.jit(lambda s, r: banded.solve(s, r, topo))(shifted, r))
    assert np.allclose((dense + shift * np.eye(topo.n_red)) @ x, r, atol=1e-10)


@pytest.mark.slow
def test_gravity_static_balance(model, equilibrium):
    m, _ = model
    st = equilibrium
    term = m.terms[0]
    _, fn, _, _ = term._forces(st.u, st.history[0], m.params.extra[0][1], m.params.X)
    weight = float(-m.params.gravity[1]) * float(jnp.sum(m.params.node_mass[:, 0]) + _beam_mass(m))
    # Floor reactions carry the whole weight (no other support).
    assert float(-jnp.sum(fn)) == pytest.approx(weight, rel=1e-8)


def _beam_mass(m):
    from bristlecrawler.fe import assembly

    ones = jnp.zeros((m.topology.n_nodes, 3)).at[:, 0].set(1.0)
    return float(jnp.sum(assembly.mass_times(ones, m.params, m.topology)[:, 0])) - float(
        jnp.sum(m.params.node_mass[:, 0])
    )


@pytest.mark.slow
def test_hht_follows_actuated_length(model, equilibrium):
    m, nodes = model
    st = equilibrium
    s0 = initial_state(m, q=st.q, history=st.history)
    L, R = nodes["left"], nodes["right"]

    def body_length(s, params):
        x = params.X + s.u[:, :2]
        return {"t": s.t, "length": jnp.linalg.norm(x[R] - x[L])}

    out = fe.solve(m, s0, 1.0, 0.05, integrator=Integrator.hht(), save=fe.SaveAt(body_length))
    assert out.ok
    expected = 100.0 - 20.0 * np.sin(np.pi * out.times / 20.0) ** 2
    assert np.allclose(out.records["length"], expected, rtol=1e-12)


def test_an_extra_term_must_subclass_term():
    """The solvers ask a term only what :class:`fe.Term` declares (its hooks have defaults),
    so an object that merely looks like a term is refused where it is added, with a line
    naming its type, instead of failing inside a compiled step."""
    from bristlecrawler import fe
    from bristlecrawler.errors import InputError

    class LooksLikeATerm:
        def residual(self, u, v, t, history, params):
            return u

        def init_history(self, topology, params):
            return ()

        def commit(self, u, v, t, history, params):
            return history

    with pytest.raises(InputError, match="LooksLikeATerm"):
        fe.Structure().add_term(LooksLikeATerm())
    floor = PenaltyFloor((0,))
    assert floor.couplings() == () and floor.active is None and not floor.freezes
    assert floor.penetration(None, None) is None
