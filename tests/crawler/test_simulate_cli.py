"""``bristlecrawler simulate``: bad input refused before any work, outputs of a run.

The FE solve itself is exercised in tests/fe and tests/crawler; here the solver is replaced
by a kinematic stand-in so that the command's validation and writing are tested quickly.
"""

import json

import numpy as np
import pytest
import xarray as xr

from bristlecrawler.scenario.load import apply_overrides, apply_values

from .kinematic import kinematic_history


@pytest.mark.parametrize(
    ("args", "word"),
    [
        (["nope"], "unknown scenario"),
        (["paper", "--set", "bristle.alpha_deg=85"], "alpha_deg"),
        (["paper", "--set", "bristle.alpha_deg=-80"], "alpha_deg"),
        (["paper", "--set", "actuation.s_max=100"], "s_max"),
        (["paper", "--set", "bristle.youngs_modulus=0"], "youngs_modulus"),
        (["paper", "--set", "bristle.thickness_tip=-1"], "thickness_tip"),
        (["paper", "--set", "contact.mu=-0.1"], "(with --set): contact.mu:"),
        (["paper", "--set", "substrate.mu=-0.1"], "(with --set): contact.mu:"),
        (["paper", "--set", "substrate.kind=foo"], "substrate.kind: 'foo' is not one of"),
        (
            ["paper", "--set", "bristle.elements=true"],
            "bristle.elements: Input should be a valid integer",
        ),
        (
            ["paper", "--set", "bristle.youngs_modulus=true"],
            "youngs_modulus: Input should be a valid number",
        ),
        (["paper", "--set", 'bristle.alpha_deg="45"'], "alpha_deg: Input should be a valid number"),
        (["paper", "--set", "solver.freeze_iterations=25"], "freeze_iterations"),
        (["paper", "--set", "nonsense"], "section.key=value"),
        (["paper", "--set", "substrate=3"], "substrate must be a table"),
        (["paper", "--set", "bristle.colour=3"], "colour"),
        (["paper", "--cycles", "0"], "cycles"),
        (["paper", "--actuator", "hydraulic"], "--actuator"),
        (["missing.toml"], "not found"),
    ],
)
def test_bad_input_one_line_exit_2_nothing_written(run_cli, tmp_path, args, word):
    out = tmp_path / "out"
    code, _stdout, err = run_cli(["simulate", *args, "--out", str(out)])
    assert code == 2
    assert word in err and err.count("\n") == 1 and "Traceback" not in err
    assert not out.exists()


def test_history_with_negative_shortening_is_refused(run_cli, tmp_path):
    csv = tmp_path / "h.csv"
    csv.write_text("t,s\n0,0\n1,5\n2,-1\n")
    toml = tmp_path / "sc.toml"
    toml.write_text(f'[actuation]\nkind = "history"\nhistory = "{csv.name}"\n')
    code, _, err = run_cli(["simulate", str(toml), "--out", str(tmp_path / "o")])
    assert code == 2 and "shortening must be >= 0" in err


@pytest.mark.slow
def test_run_writes_every_output(run_cli, tmp_path, monkeypatch):
    h = kinematic_history(cycles=2, samples=60)
    monkeypatch.setattr("bristlecrawler.jobs.simulate.solve", lambda spec, progress=None: h)
    out = tmp_path / "run"
    code, stdout, err = run_cli(["simulate", "paper", "--cycles", "2", "--out", str(out), "--json"])
    assert code == 0, err

    def no_nan(word):
        raise AssertionError(f"{word} in the JSON summary")

    summary = json.loads(stdout, parse_constant=no_nan)  # strict JSON: null, not NaN
    assert summary["max_bristle_strain"] is None  # the stand-in's bristles are one element
    for key in (
        "net_advance_mm",
        "advance_per_cycle_mm",
        "work_mJ",
        "mean_abs_connector_force_N",
        "energy_balance_rel_error",
        "wall_time_s",
        "steps",
        "newton_iterations",
    ):
        assert key in summary
    assert summary["net_advance_mm"] == pytest.approx(h.net_advance)
    assert np.sum(summary["advance_per_cycle_mm"]) == pytest.approx(h.net_advance)
    for name in (
        "crawler.nc",
        "config.json",
        "meta.json",
        "summary.json",
        "delta_vs_s.png",
        "shapes.png",
        "connector.png",
        "crawler.gif",
        "vtk/crawler.pvd",
    ):
        assert (out / name).is_file(), name
    cfg = json.loads((out / "config.json").read_text())
    assert cfg["actuation"]["cycles"] == 2 and cfg["bristle"]["alpha_deg"] == 45.0
    meta = json.loads((out / "meta.json").read_text())
    assert {"package_version", "git_revision", "command"} <= set(meta)
    with xr.open_dataset(out / "crawler.nc") as ds:
        np.testing.assert_allclose(ds["delta"].values, h.delta)
        assert ds.sizes["frame"] <= 2 * 40 + 2
    import meshio

    frame = meshio.read(sorted((out / "vtk").glob("*.vtu"))[0])
    np.testing.assert_array_equal(frame.point_data["thickness"], h.node_thickness)


def test_the_old_key_substrate_mu_in_set_runs_contact_mu(run_cli, tmp_path, monkeypatch):
    """``--set substrate.mu=...`` runs the spec of ``--set contact.mu=...``; the run folder
    writes the new key and the warning is one line."""
    seen = []

    def fake(spec, progress=None):
        seen.append(spec)
        return kinematic_history(cycles=1, samples=40)

    monkeypatch.setattr("bristlecrawler.jobs.simulate.solve", fake)
    quiet = ["--cycles", "1", "--no-figures", "--no-vtk", "--json"]
    for key, out in (("contact.mu", tmp_path / "new"), ("substrate.mu", tmp_path / "old")):
        code, _, err = run_cli(
            ["simulate", "paper", "--set", f"{key}=0.3", *quiet, "--out", str(out)]
        )
        assert code == 0, err
    assert err == "warning: substrate.mu is deprecated: use contact.mu\n"
    assert seen[0] == seen[1] and seen[1].contact.mu == 0.3
    for out in (tmp_path / "new", tmp_path / "old"):
        cfg = json.loads((out / "config.json").read_text())
        assert cfg["contact"]["mu"] == 0.3 and "mu" not in cfg["substrate"]
        assert "\n[contact]\nmu = 0.3\n" in (out / "scenario.toml").read_text()


def test_actuator_option_selects_the_sma_history(run_cli, tmp_path, monkeypatch):
    seen = {}

    def fake(spec, progress=None):
        seen["history"] = spec.actuation.history
        return kinematic_history(cycles=1, samples=40)

    monkeypatch.setattr("bristlecrawler.jobs.simulate.solve", fake)
    out = tmp_path / "run"
    code, _, err = run_cli(
        [
            "simulate",
            "paper",
            "--actuator",
            "sma",
            "--cycles",
            "1",
            "--no-figures",
            "--no-vtk",
            "--out",
            str(out),
            "--json",
        ]
    )
    assert code == 0, err
    assert seen["history"] is not None and max(seen["history"][1]) > 0  # the SMA stroke
    assert json.loads((out / "config.json").read_text())["actuation"]["kind"] == "sma"


def test_overrides_are_validated_like_the_file():
    from bristlecrawler.scenario.load import load_scenario

    sc = apply_overrides(load_scenario("paper"), ["substrate.pitch=3.5", "bristle.shear=false"])
    assert sc.substrate.pitch == 3.5 and sc.bristle.shear is False


def _never_called(spec, progress=None):
    raise AssertionError("the solver ran although the output folder was refused")


@pytest.mark.parametrize("where", ["file", "under a file", "previous run", "dead link"])
def test_an_unusable_out_folder_is_refused_before_the_solve(run_cli, tmp_path, monkeypatch, where):
    """A file, a path below a file, or a folder that already holds a run: one line, exit 2,
    the solver never runs and what was there is untouched."""
    monkeypatch.setattr("bristlecrawler.jobs.simulate.solve", _never_called)
    afile = tmp_path / "afile"
    afile.write_text("keep me\n")
    old = tmp_path / "old"
    old.mkdir()
    (old / "meta.json").write_text('{"run_id": "old"}\n')
    (old / "shapes.png").write_bytes(b"old figure")
    dead = tmp_path / "dead"
    dead.symlink_to(tmp_path / "nowhere")
    out = {"file": afile, "under a file": afile / "sub", "previous run": old, "dead link": dead}[
        where
    ]
    code, _, err = run_cli(["simulate", "paper", "--cycles", "1", "--out", str(out)])
    assert code == 2, err
    assert err.startswith("error:") and err.count("\n") == 1
    assert afile.read_text() == "keep me\n"
    assert (old / "meta.json").read_text() == '{"run_id": "old"}\n'
    assert sorted(p.name for p in old.iterdir()) == ["meta.json", "shapes.png"]


def test_history_option_runs_a_recorded_shortening(run_cli, tmp_path, monkeypatch):
    seen = {}

    def fake(spec, progress=None):
        seen["actuation"] = spec.actuation
        return kinematic_history(cycles=1, samples=40)

    monkeypatch.setattr("bristlecrawler.jobs.simulate.solve", fake)
    csv = tmp_path / 'my "h" \\ é 😀.csv'  # quotes, a backslash, non-ASCII, outside the BMP
    csv.write_text("t,s\n0,0\n10,20\n20,0\n")
    out = tmp_path / "run"
    args = ["simulate", "paper", "--history", str(csv), "--no-figures", "--no-vtk"]
    code, _, err = run_cli([*args, "--out", str(out), "--json"])
    assert code == 0, err
    assert seen["actuation"].history == ((0.0, 10.0, 20.0), (0.0, 20.0, 0.0))
    code, _, err = run_cli([*args, "--actuator", "sma", "--out", str(tmp_path / "o2")])
    assert code == 2 and "not both" in err and not (tmp_path / "o2").exists()
    code, _, err = run_cli([*args, "--cycles", "3", "--out", str(tmp_path / "o3")])
    assert code == 2 and "--cycles does not apply" in err and not (tmp_path / "o3").exists()


def test_numpy_scalars_are_plain_numbers_for_the_strict_schema():
    """A sweep's numpy values pass (strict mode refuses bools and strings, not these)."""
    from bristlecrawler.scenario.load import load_scenario

    sc = apply_values(
        load_scenario("paper"),
        {
            "bristle.elements": np.int64(30),
            "bristle.alpha_deg": np.float32(30.0),
            "substrate.pitch": np.float64(2.5),
        },
    )
    assert sc.bristle.elements == 30 and type(sc.bristle.elements) is int
    assert sc.bristle.alpha_deg == 30.0 and sc.substrate.pitch == 2.5
