"""The verification cases of ``bristlecrawler verify`` (FE vs closed forms), run once."""

import itertools
import json

import pytest
from typer.testing import CliRunner

from bristlecrawler.verification import run_all


@pytest.fixture(scope="module")
def results():
    return run_all()


@pytest.mark.slow
def test_every_case_passes(results):
    rows, doc = results
    failed = [
        f"{r.case}: {r.quantity} err {r.error:.2e} > {r.tol:.0e}" for r in rows if not r.passed
    ]
    assert not failed, failed
    assert doc["passed"]


@pytest.mark.slow
def test_convergence_order_is_two(results):
    # Corotational element with linear kinematics of the chord: O(h^2) in tip deflection.
    orders = results[1]["mesh_convergence"]["orders"]
    assert all(1.9 < p < 2.1 for p in orders), orders


@pytest.mark.slow
def test_tip_load_response_is_monotone(results):
    # More load: more deflection, more shortening, more rotation (elastica).
    runs = results[1]["cantilever_tip_load"]
    for a, b in itertools.pairwise(runs):
        assert b["u_over_L"] > a["u_over_L"] and b["v_over_L"] > a["v_over_L"]
        assert b["theta"] > a["theta"]


@pytest.mark.slow
def test_cli_json_is_one_object(results, monkeypatch):
    import typer

    import bristlecrawler.verification as verification
    from bristlecrawler.cli import verify

    monkeypatch.setattr(verification, "run_all", lambda: results)
    app = typer.Typer()
    verify.register(app)
    app.command("noop")(lambda: None)  # keep 'verify' a sub-command
    out = CliRunner().invoke(app, ["verify", "--json"])
    assert out.exit_code == 0, out.output
    doc = json.loads(out.stdout)
    assert {"PL2_EI", "u_over_L", "v_over_L", "theta"} <= set(doc["cantilever_tip_load"][0])
    assert [r["PL2_EI"] for r in doc["cantilever_tip_load"]] == [1.0, 2.0, 5.0, 10.0]
    assert doc["tapered_tip_stiffness_N_per_mm"] > 0
    assert doc["bristle_horizontal_stiffness_N_per_mm"] > 0
    table = CliRunner().invoke(app, ["verify"])
    assert table.exit_code == 0 and "tapered bristle" in table.stdout
