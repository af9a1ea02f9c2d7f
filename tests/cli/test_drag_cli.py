"""``bristlecrawler drag``: bad input is one line and exit 2 before any work; a run writes
its folder (the solver replaced by a recorded stand-in, the drag physics is tested in
tests/crawler/test_drag.py)."""

import json

import numpy as np
import pytest


@pytest.mark.parametrize(
    ("args", "words"),
    [
        (["--distance", "1"], "shorter than one groove pitch"),
        (["--direction", "sideways"], "direction"),
        (["--speed", "inf"], "speed"),
        (["--speed", "0"], "speed"),
        (["--legs", "1"], "legs"),
        (["--load", "-2"], "load"),
        (["--set", "bristle.alpha_deg=95"], "alpha_deg"),
        (["--set", "substrate.pitch=0"], "pitch"),
    ],
)
def test_bad_drag_input_is_one_line_and_exit_2(run_cli, tmp_path, args, words):
    out = tmp_path / "run"
    code, stdout, err = run_cli(["drag", "paper", *args, "--out", str(out)])
    assert code == 2 and words in err and len(err.strip().splitlines()) == 1
    assert not out.exists() and stdout == ""


def test_a_fast_carriage_is_warned_about(run_cli, tmp_path, monkeypatch):
    from bristlecrawler.crawler.drag_analysis import DragResult

    def fake(spec, test, progress=None):
        t = np.linspace(0.0, test.duration, 50)
        x = np.interp(t, *test.path())
        f = 0.2 * np.tanh(np.gradient(x, t))
        z = np.zeros_like(t)
        energies = {k: z for k in ("elastic", "kinetic", "potential", "friction", "damping")}
        energies["external"] = z
        legs = ((0, 24, 1), (24, 49, -1))
        return DragResult(
            t,
            x,
            z,
            f,
            np.stack([z, z], 1),
            np.stack([x, z], 1),
            np.full(t.size, 2),
            energies,
            2.0,
            0.27,
            0.65,
            legs,
        )

    monkeypatch.setattr("bristlecrawler.jobs.drag.solve_drag", fake)
    out = tmp_path / "run"
    code, stdout, err = run_cli(["drag", "paper", "--speed", "500", "--out", str(out), "--json"])
    assert code == 0, err
    assert "not quasi-static" in err
    summary = json.loads(stdout)
    assert summary["fp_N"] == pytest.approx(0.2, rel=1e-3)
    assert summary["fn_N"] == pytest.approx(0.2, rel=1e-3)
    assert {p.name for p in out.iterdir()} >= {"drag.nc", "drag.png", "summary.json", "meta.json"}
