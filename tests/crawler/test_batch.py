"""Designs of one structure in one compiled program (:func:`crawler.run_batch`).

A short, coarse version of the paper's run (4 elements per bristle, contact at the tips,
a 1 mm stroke in 0.4 s): each design of a batch must take the steps of its single run.
"""

import dataclasses
import functools

import numpy as np
import pytest

from bristlecrawler.crawler import run, run_batch
from bristlecrawler.errors import InputError
from bristlecrawler.scenario.convert import to_spec
from bristlecrawler.scenario.load import apply_overrides, load_scenario

SHORT = [
    "bristle.elements=4",
    "contact.nodes='tip'",
    "contact.surface=false",
    "contact.corners=false",
    "actuation.s_max=1.0",
    "actuation.period=0.4",
    "actuation.cycles=1",
    "actuation.settle_time=0.2",
]


@functools.cache
def base():
    return to_spec(apply_overrides(load_scenario("paper"), SHORT))


def design(alpha_deg=45.0, mu=0.65):
    spec = base().replace_bristles(alpha_deg=alpha_deg)
    return dataclasses.replace(spec, contact=dataclasses.replace(spec.contact, mu=mu))


DESIGNS = ((45.0, 0.65), (30.0, 0.65), (45.0, 0.3))


@functools.cache
def batch():
    return run_batch([design(*d) for d in DESIGNS])


@pytest.mark.parametrize("index", range(len(DESIGNS)))
def test_each_design_of_a_batch_takes_the_steps_of_its_single_run(index):
    single = run(design(*DESIGNS[index]))
    b = batch()
    assert b.errors[index] is None
    h = b.histories[index]
    assert h.stats["steps"] == single.stats["steps"]
    assert h.stats["rejected_steps"] == single.stats["rejected_steps"]
    assert h.net_advance == pytest.approx(single.net_advance, abs=1e-6)
    np.testing.assert_allclose(h.t, single.t, atol=1e-12)
    np.testing.assert_allclose(h.tip_position[-1], single.tip_position[-1], atol=1e-6)
