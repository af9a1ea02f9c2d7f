"""Per-design outputs: the closed forms against the exact solver, failures as values, and
one short FE design through the task a worker runs."""

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from bristlecrawler.scenario.reduced import ReducedConfig
from bristlecrawler.studies import DesignStatus, evaluate_reduced_chunk
from bristlecrawler.studies.evaluate import OUTPUTS


@given(
    s=st.lists(st.floats(0.5, 40.0), min_size=1, max_size=4),
    c=st.floats(0.05, 8.0),
    cycles=st.integers(1, 4),
)
def test_closed_form_designs_match_the_exact_solver(s, c, cycles):
    """Two bristles, sin^2 stroke: the bulk closed forms (advance, work, mean and peak
    connector force, balance) equal the exact solver's run of the same designs."""
    base = ReducedConfig(cycles=cycles, samples_per_cycle=4000).model_dump()
    values = {"s_max": np.array(s), "fp": np.full(len(s), c * base["k"])}
    bulk = evaluate_reduced_chunk(base, values, "auto")
    exact = evaluate_reduced_chunk(base, values, "exact")
    assert np.all(bulk["status"] == DesignStatus.DONE) and np.all(bulk["steps"] == 0)
    assert np.all(exact["steps"] > 0)
    for key in ("net_advance_mm", "last_cycle_advance_mm", "work_mJ", "max_abs_connector_force_N"):
        np.testing.assert_allclose(bulk[key], exact[key], rtol=1e-9, atol=1e-9)
    # The solver's mean is a trapezoidal rule over 4000 samples per cycle.
    np.testing.assert_allclose(
        bulk["mean_abs_connector_force_N"], exact["mean_abs_connector_force_N"], rtol=1e-5
    )
    assert np.all(bulk["energy_balance_rel_error"] < 1e-12)


def test_cost_of_transport_is_work_per_advance_and_nan_without_advance():
    base = ReducedConfig(cycles=3).model_dump()
    c = base["fp"] / base["k"]
    # Regime 1 (no sliding), 2 (one slide, then shakedown), 3 (steady crawling).
    res = evaluate_reduced_chunk(base, {"s_max": np.array([1.5 * c, 3 * c, 20.0])})
    assert np.isnan(res["cost_of_transport_mJ_per_mm"][0])
    np.testing.assert_allclose(res["net_advance_mm"], [0.0, 0.5 * c, 3 * 20 - 11 * c])
    np.testing.assert_allclose(res["last_cycle_advance_mm"], [0.0, 0.0, 20 - 4 * c])
    np.testing.assert_allclose(
        res["cost_of_transport_mJ_per_mm"][1:], res["work_mJ"][1:] / res["net_advance_mm"][1:]
    )
    np.testing.assert_allclose(res["advance_per_cycle_mm"], res["net_advance_mm"] / 3)


def test_a_failing_design_is_recorded_and_the_others_go_on(tmp_path):
    base = ReducedConfig(cycles=2).model_dump()
    values = {
        "s_max": np.array([10.0, 10.0, 12.0]),
        "history": np.array([None, str(tmp_path / "missing.csv"), None], dtype=object),
    }
    res = evaluate_reduced_chunk(base, values)
    np.testing.assert_array_equal(res["status"], [1, 2, 1])
    assert "missing.csv" in res["error"][1] and res["error"][0] == ""
    assert np.isnan(res["net_advance_mm"][1]) and res["net_advance_mm"][2] > 0
    assert set(res) == set(OUTPUTS) | {"status", "error"}


def test_a_failing_fe_design_is_a_value_not_an_exception(tmp_path):
    from bristlecrawler.scenario.load import load_scenario
    from bristlecrawler.studies.execute import fe_task

    base = load_scenario("paper").model_dump(mode="json")
    bad = {"actuation.kind": "history", "actuation.history": str(tmp_path / "no.csv")}
    res = fe_task(base, [bad])
    assert res["status"][0] == DesignStatus.FAILED
    assert "no.csv" in res["error"][0]


@pytest.mark.slow
def test_one_short_fe_design_through_the_worker_task():
    """The FE crawler on a mirror-symmetric set-up (vertical bristles, lands centred under
    both tips): it cannot advance, yet the actuator works against friction."""
    from bristlecrawler.scenario.load import load_scenario
    from bristlecrawler.studies.execute import fe_task

    base = load_scenario("paper-vertical").model_dump(mode="json")
    design = {
        "bristle.elements": 4,
        "contact.nodes": "tip",
        "contact.surface": False,
        "contact.corners": False,
        "substrate.phase": 0.5,
        "actuation.s_max": 0.8,
        "actuation.period": 0.4,
        "actuation.cycles": 1,
        "actuation.settle_time": 0.2,
    }
    res = fe_task(base, [design])
    out = {k: v[0] for k, v in res.items()}
    assert out["status"] == DesignStatus.DONE, out["error"]
    assert abs(out["net_advance_mm"]) < 1e-6 * 0.8
    assert out["advance_per_cycle_mm"] == out["last_cycle_advance_mm"] == out["net_advance_mm"]
    assert out["work_mJ"] > 0
    assert 0 < out["mean_abs_connector_force_N"] <= out["max_abs_connector_force_N"]
    assert np.isfinite(out["energy_balance_rel_error"]) and out["energy_balance_rel_error"] >= 0
    assert out["steps"] > 0 and out["newton_iterations"] >= out["steps"]
