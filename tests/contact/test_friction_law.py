"""The friction-law seam: the contact kernels call a law only through the abstract
:class:`FrictionLaw`, so a law of another kind is one class (the Coulomb and power laws
are two such classes, registered by name)."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from bristlecrawler._pytree import pytree
from bristlecrawler.contact import (
    CoulombLaw,
    Flat,
    FrictionLaw,
    PowerLaw,
    node_force,
    node_step,
)
from bristlecrawler.contact.coulomb import return_map
from bristlecrawler.errors import InputError


@pytree()
class DirectionalLaw(FrictionLaw):
    """Coulomb friction whose coefficient depends on the direction of sliding: mu_forward
    along +s, mu_backward along -s (a reduced substrate's directional friction). It
    overrides the kernels' three calls, not the hooks the return mapping reads."""

    mu_forward: jax.Array
    mu_backward: jax.Array
    k_n: jax.Array
    k_t: jax.Array

    def normal_force(self, g, lambda_n=0.0):
        return jnp.maximum(lambda_n - self.k_n * g, 0.0)

    def normal_energy(self, g, lambda_n=0.0):
        return 0.5 * self.normal_force(g, lambda_n) ** 2 / self.k_n

    def limit(self, p_n):
        return self.mu_forward * p_n

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


def test_laws_are_found_by_name_and_an_unknown_name_is_one_line():
    assert FrictionLaw.of("coulomb") is CoulombLaw and FrictionLaw.of("power") is PowerLaw
    with pytest.raises(InputError, match="unknown friction law 'stiction'; known: coulomb, power"):
        FrictionLaw.of("stiction")
    with pytest.raises(TypeError):
        FrictionLaw()  # the hooks are abstract


@settings(max_examples=60, deadline=None)
@given(
    g=st.floats(-2e-3, 1e-3),
    s=st.floats(-0.5, 0.5),
    a=st.floats(-0.5, 0.5),
)
def test_the_power_law_with_exponent_one_is_coulombs(g, s, a):
    c = CoulombLaw(0.65, K_N, K_T)
    p = PowerLaw(0.65, K_N, K_T, 1.0, 0.37)
    for x, y in zip(c.step(g, s, a), p.step(g, s, a), strict=True):
        np.testing.assert_allclose(y, x, rtol=1e-12, atol=1e-15)


@pytest.mark.parametrize("m", [0.5, 2.0 / 3.0, 0.8])
def test_a_sliding_point_resists_with_the_power_of_its_load(m):
    """A point pressed with load N and slid along a plane resists with mu L (N / L)^m: on
    log axes the resistance over N is a line of slope m through mu L at N = L; the
    dissipation of the step is that resistance times the slip."""
    mu, ref = 0.65, 0.3
    law = PowerLaw(mu, K_N, K_T, m, ref)
    loads = ref * np.array([0.1, 0.5, 1.0, 2.0, 8.0])
    forces = []
    for n in loads:
        f, _, (anchor, step) = _point(jnp.asarray([1.0, -n / K_N]), law)
        np.testing.assert_allclose(f[1], -n, rtol=1e-12)
        forces.append(float(f[0]))
        assert float(step.dissipation) == pytest.approx(forces[-1] * abs(float(anchor)))
    slope = np.polyfit(np.log(loads), np.log(forces), 1)[0]
    assert slope == pytest.approx(m, rel=1e-9)
    np.testing.assert_allclose(forces[2], mu * ref, rtol=1e-12)
    np.testing.assert_allclose(forces, mu * ref * (loads / ref) ** m, rtol=1e-12)


def test_the_power_laws_tangent_is_finite_at_touchdown_and_its_slip_coupling_exact():
    """d F / d p_N = m mu (p_N / L)^(m - 1): the slip tangent's normal-to-tangential term
    by autodiff; no NaN where the point has just touched or is open."""
    law = PowerLaw(0.65, K_N, K_T, 0.5, 0.3)
    for n in (0.0, 1e-12, 0.3):
        _, J, _ = _point(jnp.asarray([1.0, -n / K_N]), law)
        assert np.all(np.isfinite(J))
    n = 0.12
    _, J, _ = _point(jnp.asarray([1.0, -n / K_N]), law)
    dF = 0.5 * 0.65 * (n / 0.3) ** -0.5
    np.testing.assert_allclose(J[0, 1], -dF * K_N, rtol=1e-10)


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"exponent": 0.3}, "friction exponent must be in \\[0.5, 1\\], got 0.3"),
        ({"exponent": 1.0, "load": 0.0}, "reference load must be finite and > 0 N"),
    ],
)
def test_the_power_law_refuses_what_it_cannot_mean(kwargs, message):
    args = {"mu": 0.65, "k_n": K_N, "k_t": K_T, "exponent": 0.7, "load": 0.3} | kwargs
    with pytest.raises(InputError, match=message):
        PowerLaw(**args)


def test_the_power_laws_reference_load_is_its_own_not_the_penalty_load():
    """The penalties are sized at the penalty load; the law's L is its own setting (the
    crawler's ``contact.friction_load``, by default the weight on one bristle), refused
    with the Coulomb law."""
    from bristlecrawler.crawler.parts import Contact

    law = PowerLaw.for_reference_load(0.65, load=2.0, exponent=0.5, reference=0.3)
    assert float(law.load) == 0.3 and float(law.k_n) == pytest.approx(2.0 / 1e-3)
    assert float(law.limit(0.3)) == pytest.approx(0.65 * 0.3, rel=1e-12)
    power = Contact(friction="power", penalty_load=2.0)
    assert power.law_options(0.27) == {"exponent": pytest.approx(2 / 3), "reference": 0.27}
    given = Contact(friction="power", friction_load=0.5)
    assert given.law_options(0.27)["reference"] == 0.5
    with pytest.raises(InputError, match=r"contact\.friction_load is the power law's"):
        Contact(friction_load=0.5).check()
