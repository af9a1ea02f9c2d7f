"""``fe.motion.interp``: linear interpolation without a search loop, the same numbers as
``jnp.interp`` (values and derivatives, bit for bit, under ``jit``)."""

import jax
import jax.numpy as jnp
import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from bristlecrawler.fe.motion import interp

N_KNOTS, N_QUERIES = 17, 40
_values = jax.jit(jax.vmap(interp))
_reference = jax.jit(jax.vmap(jnp.interp))


def _grads(f):
    def loss(x, xp, fp):
        return jnp.sum(jnp.sin(jax.vmap(f)(x, xp, fp)))

    return jax.jit(jax.grad(loss, argnums=(0, 1, 2)))


_grad, _grad_reference = _grads(interp), _grads(jnp.interp)


@settings(max_examples=15, deadline=None)
@given(seed=st.integers(0, 2**31 - 1), repeated=st.booleans())
def test_interp_is_jnp_interp_bit_for_bit(seed, repeated):
    """Random increasing knots (with a repeated knot: a zero-length interval), queries
    inside, outside and on the knots: the same values and gradients as jnp.interp."""
    rng = np.random.default_rng(seed)
    xp = np.cumsum(rng.uniform(0.01, 1.0, (8, N_KNOTS)), axis=1) + rng.normal(size=(8, 1))
    if repeated:
        xp[:, 7] = xp[:, 6]
    fp = rng.normal(size=(8, N_KNOTS))
    inside = rng.uniform(xp[:, :1] - 1.0, xp[:, -1:] + 1.0, (8, N_QUERIES - N_KNOTS))
    x = np.concatenate([inside, xp], axis=1)
    np.testing.assert_array_equal(_values(x, xp, fp), _reference(x, xp, fp))
    for a, b in zip(_grad(x, xp, fp), _grad_reference(x, xp, fp), strict=True):
        np.testing.assert_array_equal(a, b)


def test_interp_holds_the_end_values_outside_and_is_linear_between():
    xp = jnp.array([0.0, 1.0, 3.0])
    fp = jnp.array([2.0, 4.0, 0.0])
    x = jnp.array([-5.0, 0.5, 2.0, 3.0, 9.0])
    np.testing.assert_allclose(interp(x, xp, fp), [2.0, 3.0, 2.0, 0.0, 0.0], rtol=0, atol=1e-15)
