"""The FE quasi-static comparison example reads two run folders: turning points and figure.

The FE runs themselves take minutes; here two folders are written by ``bristlecrawler
simulate`` with the kinematic stand-in of the solver (the reduced model's motion, which is
quasi-static), one with one cycle and one with two: at the turning points of the first
cycle the example must report the reduced model's closed-form values."""

import importlib.util
from pathlib import Path

import pytest

from bristlecrawler.reduced import closed_form

from .kinematic import kinematic_history

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def _example():
    spec = importlib.util.spec_from_file_location("qs", EXAMPLES / "quasi_static_fe.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_turning_points_of_a_quasi_static_run(run_cli, tmp_path, monkeypatch):
    ex = _example()
    folders = []
    for cycles in (1, 2):
        h = kinematic_history(cycles=cycles, samples=200)
        monkeypatch.setattr(
            "bristlecrawler.jobs.simulate.solve", lambda spec, progress=None, h=h: h
        )
        out = tmp_path / f"run{cycles}"
        code, _, err = run_cli(
            [
                "simulate",
                "paper",
                "--cycles",
                str(cycles),
                "--no-figures",
                "--no-vtk",
                "--out",
                str(out),
            ]
        )
        assert code == 0, err
        folders.append(out)
    rows = ex.compare(folders[0], folders[1], tmp_path / "fig.png")
    assert (tmp_path / "fig.png").stat().st_size > 0
    c = 0.456 / 0.48  # the two-bristle reduced crawler's F_p / k, mm
    one = rows["sin2"]
    assert one["s_peak_mm"] == pytest.approx(20.0, abs=1e-6)
    # First cycle of the paper's steady regime: Delta_net^1 = s~ - 3 c (paper eq. 4.13).
    assert one["delta_end_mm"] == pytest.approx(
        float(closed_form.net_advance(20.0, c, 1)), abs=1e-6
    )
    assert rows["sma"]["delta_end_mm"] == pytest.approx(
        float(closed_form.net_advance(20.0, c, 2)), abs=1e-6
    )
    # At full contraction the rear bristle has slid and the front one is loaded at F_p:
    # Delta = -c (the front end pulled back elastically by F_p / k).
    assert one["delta_at_peak_mm"] == pytest.approx(-c, abs=1e-6)
