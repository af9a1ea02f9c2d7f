"""The texture-prediction example's design grid: what the comparison covers."""

import importlib.util
from pathlib import Path

import pytest

from bristlecrawler.scenario.convert import to_spec

PATH = Path(__file__).resolve().parents[2] / "examples" / "texture_prediction.py"


def _example():
    spec = importlib.util.spec_from_file_location("texture_prediction", PATH)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_the_grid_covers_24_valid_designs_over_the_ranges():
    ex = _example()
    designs = ex.grid()
    assert len(set(designs)) == 24
    values = {}
    for d in designs:
        sc = ex.scenario(d)
        to_spec(sc).check()  # every design is a valid crawler
        for kv in d:
            key, v = kv.split("=")
            values.setdefault(key, set()).add(float(v))
    assert values["bristle.alpha_deg"] == {30, 45, 60}
    assert values["substrate.pitch"] == {1.5, 2, 3, 4}
    assert values["bristle.count"] == {2, 3, 4}
    assert min(values["actuation.s_max"]) >= 8 and max(values["actuation.s_max"]) <= 20


def test_a_row_compares_both_models_with_the_fe_and_a_constant_law_makes_them_one(
    monkeypatch,
):
    """The row of a design whose drag test gave a law constant over position: the
    texture model is then the paper's model, and the row says so."""
    import bristlecrawler.jobs.predict as predict
    from bristlecrawler.reduced.drag_summary import DragSummary, Sliding
    from bristlecrawler.reduced.texture import TextureLaw

    fp, fn, k = 0.2, 0.6, 0.9
    summary = DragSummary(
        k=k,
        k_unload=k,
        k_initial=k,
        along=Sliding(fp, 0.0, fp, fp, fp, 4),
        against=Sliding(fn, 0.0, fn, fn, fn, 4),
        mu_load=0.18,
        load=0.27,
        dissipation_per_mm=0.3,
        energy_balance_rel_error=1e-5,
        steps=100,
        newton_iterations=300,
        wall_time=1.0,
        texture=TextureLaw.constant(fp, fn, k, pitch=2.0),
    )
    monkeypatch.setattr(predict, "cached_drag", lambda sc, test: (summary, True))
    ex = _example()
    fe = ((17.6, 16.0), 17.83)
    row = ex.evaluate(("substrate.pitch=2.0",), fe=fe)
    assert row["pitch_mm"] == 2.0 and row["k_N_per_mm"] == k
    assert row["fe_steady_mm"] == 16.0 and row["fe_work_mJ"] == 17.83
    assert row["texture_steady_mm"] == pytest.approx(row["paper_steady_mm"], abs=1e-6)
    assert row["texture_work_mJ"] == pytest.approx(row["paper_work_mJ"], rel=1e-6)
    assert row["texture_hit"] == (abs(row["texture_steady_mm"] - 16.0) <= 1.0)
    assert row["texture_work_error"] == pytest.approx(row["texture_work_mJ"] / 17.83 - 1)
    assert "| substrate.pitch=2.0 | 2 | 16.00 |" in ex.markdown([row])
