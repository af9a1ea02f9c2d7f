"""``bristlecrawler reduced`` / ``calibrate``: outputs, JSON summaries, and bad input."""

import json
import subprocess
import sys

import numpy as np
import pytest

from bristlecrawler.reduced import closed_form


def test_reduced_paper_case_writes_everything(tmp_path, run_cli):
    out = tmp_path / "run"
    code, stdout, _ = run_cli(["reduced", "--json", "--out", str(out)])
    assert code == 0
    summary = json.loads(stdout)
    expected = float(closed_form.net_advance(20.0, 0.95, 5))
    assert summary["net_advance_mm"] == pytest.approx(expected, abs=1e-9)
    assert len(summary["advance_per_cycle_mm"]) == 5
    assert sum(summary["work_per_cycle_mJ"]) == pytest.approx(summary["work_mJ"])
    assert summary["work_mJ"] == pytest.approx(closed_form.work(20.0, 0.456, 0.48, 5))
    for name in (
        "reduced.nc",
        "delta_vs_s.png",
        "friction_law.png",
        "summary.json",
        "config.json",
        "meta.json",
    ):
        assert (out / name).stat().st_size > 0, name
    meta = json.loads((out / "meta.json").read_text())
    assert meta["package_version"] and meta["git_revision"]

    import xarray as xr

    with xr.open_dataset(out / "reduced.nc") as ds:
        assert ds["delta"].attrs["units"] == "mm"
        assert float(ds["delta"][-1]) == pytest.approx(expected, abs=1e-9)
        np.testing.assert_allclose(ds["energy_balance_residual"], 0.0, atol=1e-10)
        assert set(np.unique(ds["state"].values)) <= {-1, 0, 1}
        assert ds.sizes["event"] == summary["events"]


def test_reduced_with_history_file(tmp_path, run_cli):
    hist = tmp_path / "h.csv"
    hist.write_text("t,s\n0,0\n1,15\n2,5\n3,20\n4,0\n")
    code, stdout, _ = run_cli(
        ["reduced", "--history", str(hist), "--json", "--no-figures", "--out", str(tmp_path / "o")]
    )
    assert code == 0
    s = json.loads(stdout)
    # Cycles are excursions from s = 0: here a single one.
    assert len(s["advance_per_cycle_mm"]) == 1
    assert s["energy_balance_rel_error"] < 1e-9


def test_reduced_on_a_texture_law(tmp_path, run_cli):
    """--texture: the crawler on a drag test's texture law; a constant law is the paper's
    model (same advance and work as --fp/--fn/--k)."""
    from bristlecrawler.results.texture import TextureLaw

    law = tmp_path / "summary.json"
    law.write_text(json.dumps({"texture": TextureLaw.constant(0.456, 1.368, 0.48).to_dict()}))
    common = ["reduced", "--json", "--cycles", "2", "--samples-per-cycle", "100"]
    code, stdout, _ = run_cli([*common, "--texture", str(law), "--out", str(tmp_path / "t")])
    assert code == 0
    textured = json.loads(stdout)
    code, stdout, _ = run_cli([*common, "--no-figures", "--out", str(tmp_path / "p")])
    paper = json.loads(stdout)
    assert textured["model"] == "texture" and paper["model"] == "paper"
    np.testing.assert_allclose(textured["advance_per_cycle_mm"], paper["advance_per_cycle_mm"])
    assert textured["work_mJ"] == pytest.approx(paper["work_mJ"], rel=1e-12)
    assert (tmp_path / "t" / "texture.png").stat().st_size > 0


def test_reduced_refuses_a_file_without_a_texture_law(tmp_path, run_cli):
    bad = tmp_path / "summary.json"
    bad.write_text(json.dumps({"k_N_per_mm": 1.0}))
    code, _, err = run_cli(["reduced", "--texture", str(bad), "--out", str(tmp_path / "o")])
    assert code == 2 and "texture" in err and len(err.strip().splitlines()) == 1
    assert not (tmp_path / "o").exists()


def test_ten_bristle_peristaltic_run(tmp_path, run_cli):
    code, stdout, _ = run_cli(
        [
            "reduced",
            "--bristles",
            "10",
            "--s-max",
            "8",
            "--gait",
            "peristaltic",
            "--lag",
            "2",
            "--json",
            "--no-figures",
            "--out",
            str(tmp_path / "o"),
        ]
    )
    assert code == 0
    assert json.loads(stdout)["bristles"] == 10


def test_calibrate_json(run_cli):
    code, stdout, _ = run_cli(
        [
            "calibrate",
            "--s-max",
            "20",
            "--cycles",
            "5",
            "--advance",
            "82",
            "--work",
            "75",
            "--json",
        ]
    )
    assert code == 0
    d = json.loads(stdout)
    assert d["fp_over_k_mm"] == pytest.approx(0.947, abs=1e-3)
    assert d["fp_N"] == pytest.approx(0.455, abs=1e-3)
    assert d["k_N_per_mm"] == pytest.approx(0.480, abs=1e-3)


BAD = [
    (["reduced", "--k", "0"], "k"),
    (["reduced", "--fp", "-1"], "fp"),
    (["reduced", "--fn", "0.1"], "fn"),
    (["reduced", "--s-max", "-2"], "--s-max"),
    (["reduced", "--s-max", "100"], "s_max"),
    (["reduced", "--bristles", "1"], "bristles"),
    (["reduced", "--gait", "gallop"], "gait"),
    (["reduced", "--k", "abc"], "--k"),
    (["reduced", "--s-max", "nan"], "--s-max"),
    (["reduced", "--history", "missing.csv"], "missing.csv"),
    (["calibrate", "--s-max", "20", "--cycles", "5", "--advance", "101"], "advance"),
    (["calibrate", "--s-max", "20", "--cycles", "5", "--advance", "82", "--work", "0"], "work"),
]


@pytest.mark.parametrize(("args", "word"), BAD)
def test_bad_input_one_line_exit_2_nothing_written(args, word, tmp_path, run_cli, monkeypatch):
    monkeypatch.chdir(tmp_path)
    extra = ["--out", str(tmp_path / "o")] if args[0] == "reduced" else []
    code, _, stderr = run_cli(args + extra)
    assert code == 2
    lines = stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error:") and word in lines[0]
    assert not (tmp_path / "o").exists() and not (tmp_path / "runs").exists()


@pytest.mark.parametrize(
    ("content", "word"),
    [
        ("t,x\n0,0\n1,1\n", "lacks column"),
        ("t,s\n0,0\n1,nan\n", "non-finite"),
        ("t,s\n0,0\n2,1\n1,2\n", "increasing"),
        ("t,s\n0,0\n1,-2\n", ">= 0"),
        ("t,s\n0,0\n1,abc\n", "not both numbers"),
        ("", "empty"),
    ],
)
def test_bad_history_files(content, word, tmp_path, run_cli):
    f = tmp_path / "h.csv"
    f.write_text(content)
    code, _, stderr = run_cli(["reduced", "--history", str(f), "--out", str(tmp_path / "o")])
    assert code == 2 and word in stderr and len(stderr.strip().splitlines()) == 1
    assert not (tmp_path / "o").exists()


def test_failed_run_leaves_previous_results_intact(tmp_path, run_cli):
    out = tmp_path / "o"
    assert run_cli(["reduced", "--json", "--no-figures", "--out", str(out)])[0] == 0
    before = {p.name: p.read_bytes() for p in out.iterdir()}
    assert run_cli(["reduced", "--k", "-1", "--out", str(out)])[0] == 2
    after = {p.name: p.read_bytes() for p in out.iterdir()}
    assert before == after


def test_a_second_run_into_a_run_folder_is_refused_and_changes_nothing(tmp_path, run_cli):
    """A new run would mix its files with the old run's (a run without figures kept the
    old figures): the folder is refused, one line, exit 2, every file as it was."""
    out = tmp_path / "o"
    assert run_cli(["reduced", "--json", "--out", str(out)])[0] == 0
    before = {p.name: p.read_bytes() for p in out.iterdir()}
    code, _, err = run_cli(["reduced", "--no-figures", "--cycles", "2", "--out", str(out)])
    assert code == 2 and "already holds a run" in err and err.count("\n") == 1
    assert {p.name: p.read_bytes() for p in out.iterdir()} == before


def test_console_script_entry_point():
    proc = subprocess.run(
        [
            sys.executable,
            "-m",
            "bristlecrawler.cli.app",
            "calibrate",
            "--s-max",
            "20",
            "--cycles",
            "5",
            "--advance",
            "82",
            "--json",
        ],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert proc.returncode == 0
    assert json.loads(proc.stdout)["fp_over_k_mm"] == pytest.approx(18 / 19)


@pytest.mark.parametrize(
    "args",
    [
        ["--bristles", "10000", "--length", "10000", "--s-max", "0.5"],
        ["--bristles", "3000", "--length", "10000", "--s-max", "0.5", "--gait", "peristaltic"],
    ],
    ids=["breathing", "peristaltic"],
)
def test_a_run_past_the_cost_bound_is_refused_with_its_estimate(
    args, tmp_path, monkeypatch, run_cli
):
    """As ``simulate`` and ``drag`` refuse theirs: one line with the estimate, exit 2,
    before the solver starts and before any folder is made."""

    def never(*a, **k):
        raise AssertionError("the solver ran")

    monkeypatch.setattr("bristlecrawler.jobs.reduced.simulate", never)
    code, out, err = run_cli(["reduced", *args, "--out", str(tmp_path / "o")])
    assert code == 2 and out == "" and err.count("\n") == 1
    assert "bristles" in err and "make the work smaller" in err
    assert list(tmp_path.iterdir()) == []
