"""What ``bristlecrawler predict`` tells a user at a terminal: the design it ran, which
model made each number and what it assumed, a model that does not apply named as such (not
run quietly on changed numbers), and which model to trust where the two disagree.

The drag tests come from cache entries written here (no FE program is compiled)."""

import json
from pathlib import Path

from bristlecrawler.io.jsonio import dumps_strict
from bristlecrawler.jobs import predict
from bristlecrawler.results.texture import TextureLaw
from bristlecrawler.scenario.convert import to_spec
from bristlecrawler.scenario.load import apply_overrides, load_scenario
from terminal import cli, under_a_terminal

K, FP = 1.2, 0.22


def _cached(folder: Path, sets: list[str], fn: float) -> None:
    """A cache entry for the paper's design with ``sets``: a drag test that found F_p, F_n
    and a texture law with a wall per pitch."""
    sc = apply_overrides(load_scenario("paper"), sets)
    key = predict.cache_key(sc, predict.prediction_drag_test(to_spec(sc)))
    law = TextureLaw.sawtooth(sc.substrate.pitch, FP, K, cells=4)
    summary = {"k_N_per_mm": K, "fp_N": FP, "fn_N": fn, "texture": law.to_dict()}
    folder.mkdir(parents=True, exist_ok=True)
    entry = {"version": predict.CACHE_VERSION, "summary": summary}
    (folder / f"{key}.json").write_text(dumps_strict(entry))


def _words(text: str) -> str:
    return " ".join(text.split())


def test_reversed_friction_is_said_and_the_papers_model_is_not_run(tmp_path, run_cli):
    cache = tmp_path / "drag"
    _cached(cache, ["substrate.pitch=3"], fn=0.2)
    argv = ["predict", "--set", "substrate.pitch=3", "--cycles", "2", "--no-bristled"]
    env = {"BRISTLECRAWLER_DRAG_CACHE": str(cache), "BRISTLECRAWLER_COSTS": str(tmp_path / "c")}
    shown = _words(under_a_terminal(cli(*argv), 100, env))
    assert "paper with substrate.pitch=3: reduced models, 2 cycles" in shown
    assert "F_n = 0.200 N < F_p = 0.220 N" in shown
    assert "directional friction reversed or absent" in shown
    assert "paper's model (k, F_p, F_n) not applicable" in shown
    assert "0.00, 0.00" not in shown  # no advance made up for the model that was not run
    assert "texture-law model assumes:" in shown and "paper's model (k, F_p, F_n) assumes:" in shown


def test_the_json_says_the_same(tmp_path, monkeypatch, run_cli):
    quick = {"net_advance_mm": 1.0, "advance_per_cycle_mm": [1.0, 0.0], "work_mJ": 1.0}
    monkeypatch.setattr(predict, "bristled_result", lambda spec, cycles: (quick, None))
    monkeypatch.setenv("BRISTLECRAWLER_DRAG_CACHE", str(tmp_path / "drag"))
    _cached(tmp_path / "drag", ["substrate.pitch=3"], fn=0.2)
    code, out, _ = run_cli(["predict", "--set", "substrate.pitch=3", "--cycles", "2", "--json"])
    assert code == 0
    r = json.loads(out)
    assert r["paper"] is None and "F_n = 0.200 N < F_p = 0.220 N" in r["models"]["paper"]["not_run"]
    assert r["models"]["texture"]["not_run"] is None
    assert len(r["texture"]["advance_per_cycle_mm"]) == 2
    assert r["changes"] == ["substrate.pitch=3"]


def test_models_that_disagree_by_more_than_a_pitch_say_which_was_checked(tmp_path):
    """F_n barely above F_p: the paper's model sees almost no grip, the texture law locks
    the tips at its walls; the output points to the comparison with the FE crawler."""
    cache = tmp_path / "drag"
    _cached(cache, [], fn=0.23)
    env = {"BRISTLECRAWLER_DRAG_CACHE": str(cache), "BRISTLECRAWLER_COSTS": str(tmp_path / "c")}
    argv = ("predict", "--cycles", "2", "--no-bristled")
    shown = _words(under_a_terminal(cli(*argv, "--json"), 100, env))
    r = json.loads(shown[shown.index("{") :])
    gap = abs(r["texture"]["net_advance_mm"] - r["paper"]["net_advance_mm"]) / 2
    assert gap > r["drag"]["pitch_mm"]  # the case this test is about
    shown = _words(under_a_terminal(cli(*argv), 100, env))
    assert f"differ by {gap:.2f} mm per cycle" in shown
    assert "texture-law model came closer" in shown
    assert "docs/findings.md" in shown
