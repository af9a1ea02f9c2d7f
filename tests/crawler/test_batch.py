"""Designs of one structure in one compiled program (:func:`crawler.run_batch`).

The shared coarse structure (``tests/structures.py``: 4 elements per bristle, contact at the
tips, a 0.8 mm stroke in 0.4 s): each design of a batch must take the steps of its single
run, and the single runs share their compiled programs with the other coarse runs.
"""

import dataclasses
import functools
import re

import numpy as np
import pytest

from bristlecrawler.crawler import (
    Hold,
    ModalDamping,
    RunOptions,
    Settle,
    Stroke,
    group,
    run,
    run_batch,
)
from bristlecrawler.errors import InputError, SolverError
from bristlecrawler.scenario.load import load_scenario
from structures import COARSE, coarse_spec


@functools.cache
def base():
    return coarse_spec("paper")


def design(alpha_deg=45.0, mu=0.65, stroke=None):
    """The coarse crawler at ``alpha_deg`` and ``mu``; ``stroke`` (s_max mm, period s)
    replaces its stroke."""
    spec = base().replace_bristles(alpha_deg=alpha_deg)
    a = spec.actuation
    if stroke is not None:
        a = dataclasses.replace(a, s_max=stroke[0], period=stroke[1])
    return dataclasses.replace(spec, contact=dataclasses.replace(spec.contact, mu=mu), actuation=a)


#: The third design's stroke is shorter and slower: the stroke is a value of the programs,
#: and a design's stages end at its own times.
DESIGNS = ((45.0, 0.65), (30.0, 0.65), (45.0, 0.3, (0.6, 0.5)))


@functools.cache
def batch():
    return run_batch([design(*d) for d in DESIGNS])


@pytest.mark.slow
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


@pytest.mark.slow
def test_a_batch_making_its_line_search_trials_at_once_takes_the_same_steps():
    """``batch_trials="parallel"`` evaluates every trial of a line search in one pass and
    takes the one the sequential search stops at: the same steps, advance and Newton
    iterations as the sequential batch (the CPU's default)."""
    par = run_batch([design(*d) for d in DESIGNS], options=RunOptions(batch_trials="parallel"))
    for h, ref in zip(par.histories, batch().histories, strict=True):
        for key in ("steps", "rejected_steps", "stroke_newton_iterations"):
            assert h.stats[key] == ref.stats[key], key
        assert h.net_advance == pytest.approx(ref.net_advance, abs=1e-9)


def test_an_unknown_way_of_making_the_trials_is_refused():
    with pytest.raises(InputError, match="batch_trials"):
        RunOptions(batch_trials="lazy")


@pytest.mark.slow
def test_the_batch_counts_its_iterations_against_its_designs():
    """Each iteration of the batched loop is at most one Newton iteration of each design:
    the batch cannot take fewer iterations than its longest design, and its utilisation
    is at most 1."""
    b = batch()
    s = b.stats
    own = [h.stats["stroke_newton_iterations"] for h in b.histories]
    assert s["batch_iterations"] >= max(own)
    assert s["design_iterations"] == sum(own)
    assert 0.0 < s["utilisation"] <= 1.0
    for key in ("prepare", "settle", "modal", "stroke", "histories"):
        assert s[f"{key}_wall_time_s"] >= 0.0


@pytest.mark.slow
def test_a_failing_design_is_reported_while_the_others_finish():
    """A design whose step cannot be cut far enough (dt_min = 0.02 s) fails with its
    single run's message (where, when, why; its last attempt converged, and the
    residual it reports is round-off, which the batched program sums in its own order);
    the other design, beside it and a masked padding slot (width 3, the program of the
    batch above), ends as its single run does."""
    bad = design(45.0, 0.65)
    bad = dataclasses.replace(bad, solver=dataclasses.replace(bad.solver, dt_min=0.02))
    with pytest.raises(SolverError) as single:
        run(bad)
    b = run_batch([bad, design(*DESIGNS[1])], width=3)
    assert b.histories[0] is None
    residual = re.compile(r"\|R\| = [^,]+, \|R\|/F = ([^)]+)\)")
    assert residual.sub("", b.errors[0]) == residual.sub("", str(single.value))
    assert float(residual.search(b.errors[0]).group(1)) < bad.solver.tolerance
    assert b.errors[1] is None
    assert b.histories[1].net_advance == pytest.approx(batch().histories[1].net_advance, abs=1e-9)
    assert b.histories[1].stats["steps"] == batch().histories[1].stats["steps"]


@pytest.mark.slow
def test_a_batch_runs_the_stages_a_single_run_takes():
    """The stages of a run are the batch's too: with a stroke in chunks of 0.1 s (not the
    default) and a hold after it, each design of the batch takes its single run's steps
    (the chunk ends cap the steps, so a batch ignoring them would differ)."""
    stages = (Settle(), ModalDamping(), Stroke(chunk=0.1), Hold(0.1))
    b = run_batch([design(*d) for d in DESIGNS[:2]], stages=stages)
    for index, h in enumerate(b.histories):
        single = run(design(*DESIGNS[index]), stages)
        assert h.stats["steps"] == single.stats["steps"]
        assert h.t[-1] == pytest.approx(single.t[-1], abs=1e-12)
        assert h.net_advance == pytest.approx(single.net_advance, abs=1e-6)
    default = batch().histories[0]
    assert b.histories[0].stats["steps"] != default.stats["steps"]


def test_a_stage_a_batch_cannot_step_is_refused_before_any_work():
    class Custom:
        name = "custom"

        def span(self, ctx):
            return 0.0

        def __call__(self, ctx):
            raise AssertionError("a refused batch must not run its stages")

    with pytest.raises(InputError, match="Custom is not one"):
        run_batch([base()], stages=(Settle(), Custom()))


def test_designs_of_different_structures_are_refused_with_the_key_that_differs():
    other = base().replace_bristles(elements=6)
    with pytest.raises(InputError, match=r"bristle\.elements differs: 4 vs 6"):
        run_batch([base(), other])
    with pytest.raises(InputError, match="bristle count differs: 2 vs 3"):
        run_batch([base(), base().with_bristles(3)])


@pytest.mark.parametrize(
    ("call", "message"),
    [
        (lambda: run_batch([]), "at least one design"),
        (lambda: run_batch([base(), base()], width=1), "width 1 holds at most 1 designs, got 2"),
        (lambda: group([base(), base()], 3), "batch size 3 is larger than the 2 designs"),
        (lambda: group([], 2), "at least one design"),
        (lambda: group([base()], 0), "whole number >= 1"),
    ],
)
def test_bad_batches_are_refused_before_any_work(call, message):
    with pytest.raises(InputError, match=message):
        call()


def test_designs_are_grouped_by_structure():
    a, b = base(), base().replace_bristles(elements=6)
    tilted = design(30.0, 0.3, (2.0, 1.0))
    assert group([a, b, tilted, a, b], 2) == [[0, 2], [3], [1, 4]]


def test_a_sampled_stroke_is_another_structure_and_its_samples_are_values():
    def sampled(*s):
        t = tuple(0.1 * i for i in range(len(s)))
        a = dataclasses.replace(base().actuation, history=(t, s))
        return dataclasses.replace(base(), actuation=a)

    with pytest.raises(InputError, match="stroke form differs: sin"):
        run_batch([base(), sampled(0.0, 0.4, 0.0)])
    with pytest.raises(InputError, match="3 samples vs sampled history of 4 samples"):
        run_batch([sampled(0.0, 0.4, 0.0), sampled(0.0, 0.2, 0.4, 0.0)])
    assert group([sampled(0.0, 0.4, 0.0), sampled(0.0, 0.6, 0.0), base()], 2) == [[0, 1], [2]]


@pytest.mark.slow
def test_a_sweep_worker_runs_a_batch_and_reports_each_design():
    """The sweep's batch task (the same program: width 3, one structure): outputs per
    design, a failed design a value with its message."""
    from bristlecrawler.studies.evaluate import DesignStatus
    from bristlecrawler.studies.execute import fe_batch_task

    base_config = load_scenario("paper").model_dump(mode="json")
    short = {k: v.strip("'") for k, v in (s.split("=") for s in COARSE)}
    short = {k: {"true": True, "false": False}.get(v, v) for k, v in short.items()}
    numbers = {
        k: int(v) if v.isdigit() else float(v)
        for k, v in short.items()
        if k.startswith(("actuation", "solver"))
    }
    short = short | numbers | {"bristle.elements": 4}
    designs = [
        {"bristle.alpha_deg": 30.0},
        {"solver.dt_min": 0.02},
        {"contact.mu": 0.3, "actuation.s_max": 0.6, "actuation.period": 0.5},
    ]
    res = fe_batch_task(base_config, [short | d for d in designs], 3)
    np.testing.assert_array_equal(
        res["status"], [DesignStatus.DONE, DesignStatus.FAILED, DesignStatus.DONE]
    )
    # Its steps cannot be cut below 0.02 s where the gravity step refuses them.
    assert res["error"][1].startswith("SolverError: gravity step near t = ")
    for i, j in ((0, 1), (2, 2)):
        assert res["net_advance_mm"][i] == pytest.approx(batch().histories[j].net_advance, abs=1e-9)
        assert res["steps"][i] == batch().histories[j].stats["steps"]
