"""A sampled shortening history drives the FE crawler as the stroke it samples: its times
and values are parameters of the compiled programs (``SampledStretch``'s leaves), so
histories of one length share a program and may share a batch."""

import dataclasses

import jax
import numpy as np
import pytest

from bristlecrawler.crawler import run
from bristlecrawler.crawler.model import build
from structures import coarse_spec

SAMPLES = 41


def sampled(spec, scale=1.0):
    """``spec`` with its sin^2 stroke sampled at SAMPLES times over one period, times
    ``scale``."""
    a = spec.actuation
    t = np.linspace(0.0, a.period, SAMPLES)
    s = scale * a.s_max * np.sin(np.pi * t / a.period) ** 2
    return dataclasses.replace(spec, actuation=dataclasses.replace(a, history=(tuple(t), tuple(s))))


def _signature(spec):
    p = build(spec).model.params
    return jax.tree.structure(p), [np.shape(x) for x in jax.tree.leaves(p)]


def test_strokes_and_histories_of_one_length_build_programs_of_one_signature():
    base = coarse_spec("paper")
    other = dataclasses.replace(
        base, actuation=dataclasses.replace(base.actuation, s_max=2.0, period=1.0, cycles=3)
    )
    assert _signature(other) == _signature(base)
    assert _signature(sampled(base, 0.5)) == _signature(sampled(base))
    assert _signature(sampled(base)) != _signature(base)


@pytest.mark.slow
def test_a_sampled_stroke_moves_the_crawler_as_the_stroke_it_samples():
    """41 samples of s~ sin^2(pi t / T) interpolated linearly differ from the stroke by at
    most s~ (pi dt / T)^2 / 2, 3 micrometres here: the run follows the stroke's to within a
    hundredth of a millimetre, and its work to within a percent."""
    base = coarse_spec("paper")
    smooth, history = run(base), run(sampled(base))
    assert history.net_advance == pytest.approx(smooth.net_advance, abs=1e-2)
    w, w_sampled = smooth.connector_work[-1], history.connector_work[-1]
    assert w > 0 and w_sampled == pytest.approx(w, rel=1e-2)
    assert np.max(history.s) == pytest.approx(np.max(smooth.s), abs=1e-2)
