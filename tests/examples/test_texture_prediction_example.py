"""The texture-prediction example's design grid: what the comparison covers."""

import importlib.util
from pathlib import Path

import numpy as np
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


def _constant_law_drag(fp=0.2, fn=0.6, k=0.9):
    """A drag test's summary whose texture law is constant over position."""
    from bristlecrawler.results.drag import DragSummary, Sliding
    from bristlecrawler.results.texture import TextureLaw

    return DragSummary(
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


def test_a_row_compares_both_models_with_the_fe_and_a_constant_law_makes_them_one(
    monkeypatch,
):
    """The row of a design whose drag test gave a law constant over position: the
    texture model is then the paper's model, and the row says so."""
    import bristlecrawler.jobs.predict as predict

    k = 0.9
    summary = _constant_law_drag(k=k)
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
    assert row["warnings"] is None  # a stored FE result: its warnings are not known


def _kinked_run():
    """A stand-in for an FE run (the kinematic crawler of tests/crawler) whose one
    bristle is bent, in its last frame, into an arc of radius 0.5 mm at a section 0.8 mm
    thick: a bending strain of about 0.8, outside the beam model."""
    import dataclasses

    spec = importlib.util.spec_from_file_location(
        "kinematic", Path(__file__).resolve().parents[1] / "crawler" / "kinematic.py"
    )
    kinematic = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(kinematic)
    n = 12
    phi = np.linspace(0.0, 1.2, n)
    arc = 0.5 * np.column_stack([np.sin(phi), 1.0 - np.cos(phi)])
    straight = np.column_stack([np.linspace(0.0, 1.0, n), np.zeros(n)])
    return dataclasses.replace(
        kinematic.kinematic_history(cycles=2, samples=40),
        frame_t=np.array([0.0, 1.0]),
        frame_nodes=np.stack([straight, arc]),
        lines=np.column_stack([np.arange(n - 1), np.arange(1, n)]),
        line_kind=np.full(n - 1, 2),
        node_thickness=np.full(n, 0.8),
    )


def test_a_design_whose_fe_run_warns_carries_the_warning_to_its_row_and_table(monkeypatch, capsys):
    """An FE run with a bristle strain outside the beam model: the row holds the warning
    that ``bristlecrawler simulate`` prints for that run, and the table shows it."""
    import bristlecrawler.crawler as crawler
    import bristlecrawler.jobs.predict as predict
    from bristlecrawler.jobs.simulate import summarize
    from bristlecrawler.scenario.load import load_scenario

    summary = _constant_law_drag()
    monkeypatch.setattr(predict, "cached_drag", lambda sc, test: (summary, True))
    h = _kinked_run()
    monkeypatch.setattr(crawler, "run", lambda spec: h)
    expected = summarize(h, load_scenario("paper"))["warnings"]
    assert len(expected) == 1 and "outside the beam model" in expected[0]
    ex = _example()
    row = ex.evaluate(("substrate.pitch=2.0",))
    assert row["warnings"] == expected
    assert row["fe_advance_per_cycle_mm"] == pytest.approx(h.advance_per_cycle())
    assert row["fe_work_mJ"] == pytest.approx(h.connector_work[-1])
    assert ex.markdown([row]).endswith(f"| {expected[0]} |")
    rows = ex.main(["--fe", "--only", "0"])
    assert rows[0]["warnings"] == expected
    table = capsys.readouterr().out.splitlines()
    assert table[0].endswith("why")
    assert table[1].startswith(rows[0]["design"]) and table[1].endswith(expected[0])
