"""``bristlecrawler synth-recording`` and ``bristlecrawler analyze``."""

import json

import pytest


@pytest.mark.parametrize("ext", [".csv", ".tdms"])
def test_synthesize_then_analyze(tmp_path, run_cli, ext):
    rec = tmp_path / f"trial{ext}"
    assert run_cli(["synth-recording", str(rec), "--actuator", "sin2", "--seed", "5"])[0] == 0
    code, stdout, _ = run_cli(["analyze", str(rec), "--json", "--out", str(tmp_path / "a")])
    assert code == 0
    d = json.loads(stdout)
    for key in (
        "cycles",
        "net_advance_mm",
        "advance_per_cycle_mm",
        "fp_over_k_mm",
        "fp_over_k_ci_mm",
    ):
        assert key in d
    assert d["cycles"] == 5 and len(d["advance_per_cycle_mm"]) == 5
    assert d["fp_over_k_mm"] == pytest.approx(0.95, rel=0.02)
    assert (tmp_path / "a" / "analysis.png").stat().st_size > 0
    assert json.loads((tmp_path / "a" / "analysis.json").read_text())["cycles"] == 5


@pytest.mark.parametrize(
    ("args", "word"),
    [
        (["analyze", "missing.csv"], "not found"),
        (["analyze", "REC", "--left", "nope"], "nope"),
        (["analyze", "REC", "--work", "-3"], "--work"),
        (["synth-recording", "x.xlsx"], ".csv or .tdms"),
        (["synth-recording", "x.csv", "--actuator", "steam"], "actuator"),
    ],
)
def test_bad_input(tmp_path, run_cli, monkeypatch, args, word):
    monkeypatch.chdir(tmp_path)
    rec = tmp_path / "r.csv"
    rec.write_text("time_s,left_mm,right_mm\n" + "".join(f"{i / 100},0,0\n" for i in range(20)))
    args = [str(rec) if a == "REC" else a for a in args]
    code, _, err = run_cli(args)
    assert code == 2 and word in err and len(err.strip().splitlines()) == 1
    assert not (tmp_path / "runs").exists()
