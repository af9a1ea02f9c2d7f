"""Prescribed motions: their numbers are parameters of a compiled program, not constants."""

import jax
import jax.numpy as jnp
import pytest

from bristlecrawler.crawler.actuation import DelayedSin2, SampledStretch
from bristlecrawler.fe.motion import Constant, TimeFunction, as_motion


def test_a_pytree_stroke_is_kept_and_strokes_share_one_trace():
    a = DelayedSin2(20.0, 20.0, 0.5, 5.0)
    assert as_motion(a) is a
    traces = []

    @jax.jit
    def value(motion, t):
        traces.append(None)
        return motion(t)

    # t = delay + T/2: the peak shortening of each stroke
    assert value(as_motion(a), 10.5) == pytest.approx(-20.0)
    assert value(as_motion(DelayedSin2(8.0, 4.0, 0.2, 1.0)), 2.2) == pytest.approx(-8.0)
    assert len(traces) == 1
    s = SampledStretch(jnp.array([0.0, 1.0]), jnp.array([0.0, 2.0]), 0.5)
    assert as_motion(s) is s
    assert float(s(1.0)) == pytest.approx(-1.0)


def test_a_plain_function_is_wrapped_and_a_number_is_constant():
    m = as_motion(lambda t: 2.0 * t)
    assert isinstance(m, TimeFunction)
    assert float(m(1.5)) == pytest.approx(3.0)
    # a PyTree with a leaf that is no number cannot be a parameter: it is wrapped
    labelled = jax.tree_util.Partial(lambda t, label: 2.0 * t, label="stroke")
    assert isinstance(as_motion(labelled), TimeFunction)
    assert float(as_motion(labelled)(1.5)) == pytest.approx(3.0)
    c = as_motion(3)
    assert isinstance(c, Constant) and float(c(7.0)) == 3.0
