"""The reduced models' plug-in point: every hook named on an abstract class, and the
callers (simulate, the NetCDF output, from_drag) asking only through those hooks."""

import dataclasses

import numpy as np
import pytest

from bristlecrawler.errors import InputError
from bristlecrawler.reduced import ReducedCrawler, Sin2Stroke, TexturedCrawler, simulate
from bristlecrawler.reduced.model import ReducedModel
from bristlecrawler.results import TextureLaw


def test_the_models_are_registered_by_name():
    assert ReducedModel.registered["paper"] is ReducedCrawler
    assert ReducedModel.registered["texture"] is TexturedCrawler


def test_a_model_without_every_hook_cannot_be_made():
    @dataclasses.dataclass(frozen=True)
    class Half(ReducedModel):
        segment_lengths: np.ndarray

        @property
        def n_bristles(self):
            return 2

    with pytest.raises(TypeError, match="abstract"):
        Half(np.array([10.0]))


@dataclasses.dataclass(frozen=True)
class _Counted(ReducedCrawler):
    """The paper's model, counting its solves: a model plugged in by its hooks alone."""

    calls: list = dataclasses.field(default_factory=list, compare=False)

    def solve(self, t, shortening, cycle_bounds=None):
        self.calls.append(t.size)
        return super().solve(t, shortening, cycle_bounds)


def test_simulate_runs_a_model_through_its_solve_hook():
    paper = ReducedCrawler.two_bristle()
    counted = _Counted(paper.k, paper.fp, paper.fn, paper.segment_lengths)
    ours = simulate(counted, Sin2Stroke(20.0, 20.0), cycles=2, samples_per_cycle=200)
    theirs = simulate(paper, Sin2Stroke(20.0, 20.0), cycles=2, samples_per_cycle=200)
    assert counted.calls == [theirs.t.size]
    np.testing.assert_array_equal(ours.delta, theirs.delta)
    np.testing.assert_array_equal(ours.work, theirs.work)


def test_simulate_refuses_what_is_not_a_reduced_model():
    with pytest.raises(InputError, match="not a reduced model: dict"):
        simulate({"k": 1.0}, Sin2Stroke(20.0, 20.0))


def test_a_texture_s_laws_and_its_paper_model_are_hooks():
    law = TextureLaw.constant(fp=0.4, fn=0.8, k=0.5, pitch=2.0)
    textured = TexturedCrawler.uniform(law, 3, 60.0)
    assert textured.texture_laws() == (law,) * 3
    paper = textured.paper_crawler()
    assert paper.texture_laws() is None and paper.paper_crawler() is paper
    np.testing.assert_array_equal(paper.fp, [0.4] * 3)
    np.testing.assert_array_equal(paper.fn, [0.8] * 3)
