"""Typed run and design metrics: the JSON keys the output files have always had, and the
values the closed forms give."""

import math

import numpy as np
import pytest

from bristlecrawler.reduced import ReducedCrawler, Sin2Stroke, closed_form, simulate
from bristlecrawler.results.metrics import DESIGN_OUTPUTS, DesignMetrics, RunMetrics

#: The keys of the files written before the typed results (summary.json, the study store).
RUN_KEYS = ["net_advance_mm", "advance_per_cycle_mm", "work_mJ"]
DESIGN_KEYS = [
    "net_advance_mm",
    "advance_per_cycle_mm",
    "last_cycle_advance_mm",
    "work_mJ",
    "cost_of_transport_mJ_per_mm",
    "mean_abs_connector_force_N",
    "max_abs_connector_force_N",
    "energy_balance_rel_error",
    "steps",
    "newton_iterations",
    "wall_time_s",
]


def _paper_run(cycles=3):
    return simulate(ReducedCrawler.two_bristle(), Sin2Stroke(20.0, 20.0), cycles=cycles)


def test_run_metrics_keep_the_file_keys_and_read_back():
    m = RunMetrics.from_reduced(_paper_run())
    data = m.to_dict()
    assert list(data) == RUN_KEYS
    assert RunMetrics.from_dict(data) == m
    assert RunMetrics.from_dict(data | {"other_key": 1}) == m


def test_run_metrics_of_the_papers_crawler_are_the_closed_forms():
    m = RunMetrics.from_reduced(_paper_run(3))
    c = 0.95
    assert m.net_advance == pytest.approx(closed_form.net_advance(20.0, c, 3), rel=1e-9)
    assert sum(m.advance_per_cycle) == pytest.approx(m.net_advance, rel=1e-12)
    assert m.advance_per_cycle[0] == pytest.approx(closed_form.net_advance_first(20.0, c))
    assert m.work == pytest.approx(closed_form.work(20.0, 0.95 * 0.48, 0.48, 3), rel=1e-9)


def test_design_metrics_keep_the_store_keys_in_order():
    m = DesignMetrics.from_reduced(_paper_run(2), 2)
    assert list(m.to_dict()) == [k for k in DESIGN_KEYS if k != "wall_time_s"]
    timed = DesignMetrics(**{**m.__dict__, "wall_time": 1.5})
    assert list(timed.to_dict()) == DESIGN_KEYS
    assert list(DESIGN_OUTPUTS) == DESIGN_KEYS


def test_design_metrics_derive_per_cycle_advance_and_cost_of_transport():
    m = DesignMetrics.from_reduced(_paper_run(2), 2)
    d = m.to_dict()
    assert d["advance_per_cycle_mm"] == pytest.approx(m.net_advance / 2)
    assert d["cost_of_transport_mJ_per_mm"] == pytest.approx(m.work / m.net_advance)
    assert d["last_cycle_advance_mm"] == pytest.approx(closed_form.net_advance_later(20.0, 0.95))
    # A crawler that does not advance has no cost of transport.
    still = DesignMetrics(**{**m.__dict__, "net_advance": 0.0})
    assert math.isnan(still.cost_of_transport)


def test_design_metrics_of_an_fe_summary():
    summary = {
        "net_advance_mm": 12.5,
        "advance_per_cycle_mm": [6.0, 6.5],
        "work_mJ": 30.0,
        "mean_abs_connector_force_N": 0.7,
        "max_abs_connector_force_N": 1.9,
        "energy_balance_rel_error": 0.01,
        "steps": 500,
        "newton_iterations": 1500,
        "wall_time_s": 33.0,
        "warnings": [],
    }
    d = DesignMetrics.from_summary(summary, 2).to_dict()
    assert list(d) == DESIGN_KEYS
    assert d["last_cycle_advance_mm"] == 6.5 and d["advance_per_cycle_mm"] == 6.25
    assert d["cost_of_transport_mJ_per_mm"] == pytest.approx(30.0 / 12.5)
    empty = DesignMetrics.from_summary(summary | {"advance_per_cycle_mm": []}, 1)
    assert math.isnan(empty.last_cycle_advance)


def test_design_metrics_hold_arrays_over_a_chunk():
    m = DesignMetrics(
        net_advance=np.array([2.0, -1.0]),
        last_cycle_advance=np.array([1.0, -0.5]),
        cycles=np.array([2.0, 2.0]),
        work=np.array([4.0, 4.0]),
        mean_abs_connector_force=np.zeros(2),
        max_abs_connector_force=np.zeros(2),
        energy_balance_rel_error=np.zeros(2),
        steps=np.zeros(2),
        newton_iterations=np.zeros(2),
    )
    np.testing.assert_array_equal(m.advance_per_cycle, [1.0, -0.5])
    np.testing.assert_array_equal(m.cost_of_transport, [2.0, np.nan])


def test_a_null_in_a_summary_file_reads_as_nan():
    """JSON writes NaN as null (strict JSON): reading a run whose advance is NaN back
    gives NaN, not an error."""
    import json
    import math

    from bristlecrawler.results.metrics import RunMetrics

    text = '{"net_advance_mm": null, "advance_per_cycle_mm": [1.5, null], "work_mJ": 2}'
    m = RunMetrics.from_dict(json.loads(text))
    assert math.isnan(m.net_advance) and math.isnan(m.advance_per_cycle[1])
    assert (m.advance_per_cycle[0], m.work) == (1.5, 2.0)
