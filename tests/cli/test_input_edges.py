"""The edges of input validation: files that cannot be read, odd encodings and nesting,
output paths, geometry checked before the solve, warnings, and strict JSON."""

import json
import os
import warnings
from pathlib import Path

import pytest

from bristlecrawler.errors import InputError
from bristlecrawler.jobs.simulate import quality_warnings
from bristlecrawler.reduced.strokes import read_history_csv
from bristlecrawler.scenario.load import apply_overrides, load_scenario

UNREADABLE = Path("/proc/self/mem")  # a file that exists and fails to read (EIO), even as root
needs_unreadable = pytest.mark.skipif(not UNREADABLE.exists(), reason="needs /proc/self/mem")


def _one_error_line(code, err):
    assert code == 2, err
    assert err.startswith("error: ") and err.count("\n") == 1, err


def test_a_history_with_a_byte_order_mark_is_read(tmp_path, run_cli):
    """Spreadsheet programs start a UTF-8 CSV with a byte-order mark."""
    f = tmp_path / "h.csv"
    f.write_bytes("\ufefft,s\n0,0\n10,12\n20,0\n".encode())
    st = read_history_csv(str(f))
    assert st.s_max == 12.0 and st.duration() == 20.0
    code, out, err = run_cli(
        ["reduced", "--history", str(f), "--json", "--no-figures", "--out", str(tmp_path / "o")]
    )
    assert code == 0, err
    assert json.loads(out)["samples"] == 3


@needs_unreadable
@pytest.mark.parametrize("command", ["reduced", "simulate", "analyze", "scenario"])
def test_a_file_that_cannot_be_read_is_one_line(tmp_path, run_cli, command):
    link = tmp_path / ("s.toml" if command == "scenario" else "f.csv")
    link.symlink_to(UNREADABLE)
    args = {
        "reduced": ["reduced", "--history", str(link)],
        "simulate": ["simulate", "paper", "--history", str(link)],
        "analyze": ["analyze", str(link)],
        "scenario": ["simulate", str(link)],
    }[command]
    code, _, err = run_cli([*args, "--out", str(tmp_path / "o")])
    _one_error_line(code, err)
    assert "cannot read" in err and str(link) in err
    assert not (tmp_path / "o").exists()


@pytest.mark.parametrize(
    ("toml", "word"),
    [
        ('[actuation]\nkind = "history"\nhistory = 5\n', "actuation.history"),
        ("a = " + "[" * 3000 + "]" * 3000 + "\n", "nested too deeply"),
        ("actuation = 5\n", "actuation"),
    ],
)
def test_odd_scenario_files(tmp_path, run_cli, toml, word):
    f = tmp_path / "s.toml"
    f.write_text(toml)
    code, _, err = run_cli(["simulate", str(f), "--out", str(tmp_path / "o")])
    _one_error_line(code, err)
    assert word in err


def test_a_set_value_nested_too_deeply(run_cli, tmp_path):
    code, _, err = run_cli(
        [
            "simulate",
            "--set",
            "substrate.points=" + "[" * 3000 + "]" * 3000,
            "--out",
            str(tmp_path / "o"),
        ]
    )
    _one_error_line(code, err)
    assert "nested too deeply" in err


def test_an_out_name_too_long_for_the_file_system(tmp_path, run_cli):
    name = tmp_path / ("x" * (os.pathconf(tmp_path, "PC_NAME_MAX") + 1))
    code, _, err = run_cli(["reduced", "--no-figures", "--out", str(name)])
    _one_error_line(code, err)
    assert "too long" in err and len(err) < 300
    assert list(tmp_path.iterdir()) == []


def test_synth_recording_never_overwrites_without_replace(tmp_path, run_cli):
    f = tmp_path / "r.csv"
    f.write_text("mine\n")
    code, _, err = run_cli(["synth-recording", str(f), "--cycles", "1"])
    _one_error_line(code, err)
    assert "exists" in err and "--replace" in err and f.read_text() == "mine\n"
    code, _, err = run_cli(["synth-recording", str(f), "--cycles", "1", "--replace"])
    assert code == 0, err
    assert f.read_text().startswith("time_s,")
    (tmp_path / "d.csv").mkdir()
    for target in (tmp_path / "d.csv", f / "below.csv"):
        code, _, err = run_cli(["synth-recording", str(target), "--cycles", "1"])
        _one_error_line(code, err)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["d.csv", "r.csv"]


def test_bristles_that_would_overlap_are_refused_before_the_solve(run_cli, tmp_path):
    """Body 100 mm, bristles 5 mm at 45 degrees, clamps 3 mm thick: at a shortening of
    99 mm the clamps are 1 mm apart, less than 5 sin 45 + 3 = 6.54 mm."""
    code, _, err = run_cli(
        ["simulate", "--set", "actuation.s_max=99", "--out", str(tmp_path / "o")]
    )
    _one_error_line(code, err)
    assert "overlap" in err and "6.54 mm" in err
    sc = load_scenario("paper")
    with pytest.raises(InputError, match="overlap"):
        apply_overrides(sc, ["actuation.s_max=93.5"])  # gap 6.5 mm
    assert apply_overrides(sc, ["actuation.s_max=93.4"]).actuation.s_max == 93.4
    # Vertical bristles reach nothing along the body: only the clamps' thickness counts.
    vertical = apply_overrides(sc, ["bristle.alpha_deg=0", "actuation.s_max=96.9"])
    assert vertical.actuation.s_max == 96.9
    with pytest.raises(InputError, match="overlap"):
        apply_overrides(sc, ["bristle.alpha_deg=0", "actuation.s_max=97"])


@pytest.mark.parametrize(
    ("assignment", "word"),
    [
        ("gravity=0", "gravity"),
        ("body.link_length=1e300", "body.link_length"),
        ("substrate.phase=1e308", "substrate.phase"),
        ("damping.a0=inf", "damping.a0"),
        ("actuation.period=1e308", "actuation.period"),
        ("actuation.cycles=10000", "time steps"),
    ],
)
def test_messages_name_the_parameter(run_cli, tmp_path, assignment, word):
    code, _, err = run_cli(["simulate", "--set", assignment, "--out", str(tmp_path / "o")])
    _one_error_line(code, err)
    assert word in err


def test_a_recording_with_absurd_values_writes_nothing(tmp_path, run_cli):
    rec = tmp_path / "r.csv"
    assert run_cli(["synth-recording", str(rec), "--actuator", "sin2", "--cycles", "2"])[0] == 0
    rows = rec.read_text().splitlines()
    cells = rows[40].split(",")
    cells[1] = "1e308"
    rows[40] = ",".join(cells)
    rec.write_text("\n".join(rows) + "\n")
    code, _, err = run_cli(["analyze", str(rec), "--out", str(tmp_path / "a")])
    _one_error_line(code, err)
    assert "channel left sample 39 is 1e+308 mm" in err
    assert not (tmp_path / "a").exists()


def test_library_warnings_are_held_back_behind_an_error(run_cli, tmp_path, monkeypatch):
    def noisy(*args, **kwargs):
        warnings.warn("invalid value encountered in divide", UserWarning, stacklevel=1)
        raise InputError("the recording is bad")

    monkeypatch.setattr("bristlecrawler.experiment.read_recording", noisy)
    code, out, err = run_cli(["analyze", str(tmp_path / "r.csv"), "--out", str(tmp_path / "a")])
    assert (code, out, err) == (2, "", "error: the recording is bad\n")


def test_warnings_of_a_successful_command_are_one_line_each(run_cli, monkeypatch):
    from bristlecrawler.reduced.calibration import Calibration

    def noisy(*args, **kwargs):
        for _ in range(3):
            warnings.warn("overflow\nencountered   in exp", UserWarning, stacklevel=1)
        return Calibration(0.95, 3)

    monkeypatch.setattr("bristlecrawler.reduced.calibration.calibrate", noisy)
    args = ["calibrate", "--s-max", "20", "--cycles", "5", "--advance", "82", "--json"]
    code, out, err = run_cli(args)
    assert code == 0 and json.loads(out)["fp_over_k_mm"] == 0.95
    assert err == "warning: overflow encountered in exp\n"


def test_runs_out_of_their_normal_range_are_flagged():
    """The paper runs close their energy balance to 7-9 % of the work and use a Newton
    tolerance of 1e-8; a friction-free run (51 %) or a loose tolerance is flagged."""
    sc = load_scenario("paper")
    assert quality_warnings(0.086, sc) == []
    (w,) = quality_warnings(0.51, apply_overrides(sc, ["contact.mu=0"]))
    assert "51%" in w and "contact.mu = 0" in w
    (w,) = quality_warnings(0.05, apply_overrides(sc, ["solver.tolerance=1e-4"]))
    assert "solver.tolerance = 0.0001" in w
    assert quality_warnings(float("nan"), sc)  # a balance that could not be computed


def test_a_flagged_simulate_run_says_so_on_stderr(run_cli, tmp_path, monkeypatch):
    from tests.crawler.kinematic import kinematic_history

    monkeypatch.setattr(
        "bristlecrawler.jobs.simulate.solve", lambda spec, progress=None: kinematic_history(1, 40)
    )
    out = tmp_path / "o"
    args = ["simulate", "--set", "solver.tolerance=1e-3", "--no-figures", "--no-vtk", "--json"]
    code, stdout, err = run_cli([*args, "--out", str(out)])
    assert code == 0, err
    assert "warning: solver.tolerance = 0.001 is looser" in err
    summary = json.loads((out / "summary.json").read_text(), parse_constant=_refuse)
    assert any("solver.tolerance" in w for w in summary["warnings"])
    json.loads((out / "config.json").read_text(), parse_constant=_refuse)
    json.loads((out / "meta.json").read_text(), parse_constant=_refuse)
    json.loads(stdout, parse_constant=_refuse)


def _refuse(name):
    raise AssertionError(f"{name} is not JSON")
