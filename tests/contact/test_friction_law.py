"""The friction-law protocol: the contact kernels call a law only through it, so a law of
another kind is one class, and the Coulomb law is one such class."""

import dataclasses

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from bristlecrawler.contact import CoulombLaw, Flat, FrictionLaw, node_force, node_step
from bristlecrawler.contact.coulomb import return_map


@jax.tree_util.register_dataclass
@dataclasses.dataclass(frozen=True)
class DirectionalLaw:
    """Coulomb friction whose coefficient depends on the direction of sliding: mu_forward
    along +s, mu_backward along -s (a reduced substrate's directional friction)."""

    mu_forward: jax.Array
    mu_backward: jax.Array
    k_n: jax.Array
    k_t: jax.Array

    def _coulomb(self, s, anchor):
        mu = jnp.where(s - anchor >= 0.0, self.mu_forward, self.mu_backward)
        return CoulombLaw(mu, self.k_n, self.k_t)

    def step(self, g, s, anchor, lambda_n=0.0, mode=None):
        return return_map(g, s, anchor, self._coulomb(s, anchor), lambda_n, mode)

    def forces(self, g, s, anchor, lambda_n=0.0, mode=None):
        st = self.step(g, s, anchor, lambda_n, mode)
        return -st.p_n, st.f_t

    def potential(self, g, s, anchor, lambda_n=0.0):
        return self._coulomb(s, anchor).potential(g, s, anchor, lambda_n)

    def penetration(self, p_n):
        return p_n / self.k_n

    def stored_energy(self, p_n, f_t):
        return 0.5 * p_n**2 / self.k_n + 0.5 * f_t**2 / self.k_t


K_N, K_T, W = 1e3, 5e2, 0.3


@jax.jit
def _point(x, law):
    """The point kernel's force, its tangent and its committed step, in one program."""

    def force(x):
        return node_force(x, 0.0, Flat(), law)

    return force(x), jax.jacfwd(force)(x), node_step(x, 0.0, Flat(), law)


def test_the_coulomb_law_is_a_friction_law_and_its_methods_are_the_kernels():
    law = CoulombLaw(0.65, K_N, K_T)
    assert isinstance(law, FrictionLaw) and isinstance(
        DirectionalLaw(0.2, 0.9, K_N, K_T), FrictionLaw
    )
    for name in ("step", "forces", "potential", "penetration", "stored_energy"):
        assert callable(getattr(law, name))
    g, s, a = jnp.asarray([-W / K_N, 1e-3]), jnp.asarray([0.2, 0.0]), jnp.asarray([0.0, 0.0])
    st = law.step(g, s, a)
    ref = return_map(g, s, a, law)
    assert all(np.array_equal(x, y) for x, y in zip(st, ref, strict=True))
    fg, fs = law.forces(g, s, a)
    np.testing.assert_array_equal(fg, -ref.p_n)
    np.testing.assert_array_equal(fs, ref.f_t)
    # the potential's gradient is the forces (p_N held in the friction part)
    dg, ds = jax.grad(lambda g, s: law.potential(g, s, a), argnums=(0, 1))(g, s)
    np.testing.assert_allclose(dg, fg, rtol=1e-12)
    np.testing.assert_allclose(ds, fs, rtol=1e-12)
    assert float(law.penetration(W)) == pytest.approx(W / K_N)
    assert float(law.stored_energy(W, 0.1)) == pytest.approx(0.5 * W**2 / K_N + 0.005 / K_T)


@pytest.mark.parametrize("direction", [1.0, -1.0])
def test_a_law_of_another_kind_drives_the_point_kernel(direction):
    """A point pressed into a flat substrate with load W and slid one way resists with
    mu_forward W, the other way with mu_backward W: the kernel takes the new law as it
    is, through the protocol alone."""
    law = DirectionalLaw(0.2, 0.9, K_N, K_T)
    x = jnp.asarray([direction * 1.0, -W / K_N])
    f, J, (anchor, st) = _point(x, law)
    mu = 0.2 if direction > 0 else 0.9
    np.testing.assert_allclose(f, [direction * mu * W, -W], rtol=1e-12)
    # slid to the limit: the anchor trails the point by the stick drift mu W / k_t
    assert float(anchor) == pytest.approx(direction * (1.0 - mu * W / K_T))
    assert float(st.dissipation) == pytest.approx(mu * W * abs(float(anchor)))
    # and its tangent by autodiff is the slip tangent: no d f_x / d x, mu k_n along y
    np.testing.assert_allclose(J, [[0.0, -direction * mu * K_N], [0.0, K_N]], atol=1e-9)
