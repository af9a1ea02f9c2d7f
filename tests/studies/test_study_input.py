"""Study files: design expansion, and bad input refused with one line, exit 2, nothing
written (no Dask cluster is started for any of these)."""

import json

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from bristlecrawler.errors import InputError
from bristlecrawler.studies import SweepOptions, available_studies, plan, run_sweep


def _study(tmp_path, text, name="s.toml"):
    path = tmp_path / name
    path.write_text(text)
    return str(path)


REDUCED = """
name = "t"
model = "reduced"
[set]
cycles = 3
[axes]
{axes}
"""


def test_grid_is_every_combination_in_c_order(tmp_path):
    p = plan(_study(tmp_path, REDUCED.format(axes="s_max = [10.0, 20.0, 30.0]\nfp = [0.2, 0.4]")))
    d = p.designs
    assert d.dims == (("s_max", 3), ("fp", 2))
    assert d.n == 6
    np.testing.assert_array_equal(d.values["s_max"], [10, 10, 20, 20, 30, 30])
    np.testing.assert_array_equal(d.values["fp"], [0.2, 0.4] * 3)
    assert d.overrides(3) == {"s_max": 20.0, "fp": 0.4}


def test_zip_pairs_the_axes_and_needs_one_length(tmp_path):
    text = REDUCED.format(axes="s_max = [10.0, 20.0]\nfp = { linspace = [0.2, 0.4, 2] }")
    p = plan(_study(tmp_path, 'combine = "zip"\n' + text))
    assert p.designs.dims == (("design", 2),)
    assert p.designs.overrides(1) == {"s_max": 20.0, "fp": 0.4}
    bad = REDUCED.format(axes="s_max = [10.0, 20.0]\nfp = [0.2, 0.3, 0.4]")
    with pytest.raises(InputError, match="one length"):
        plan(_study(tmp_path, 'combine = "zip"\n' + bad))


def test_integer_keys_take_integers_and_logspace_is_geometric(tmp_path):
    text = REDUCED.format(
        axes="bristles = { linspace = [2, 6, 5] }\nk = { logspace = [0.1, 10.0, 3] }"
    )
    p = plan(_study(tmp_path, text.replace("cycles = 3", "cycles = 3\ns_max = 5.0")))
    assert p.designs.values["bristles"].dtype.kind == "i"
    np.testing.assert_allclose(p.designs.coords["k"][1], [0.1, 1.0, 10.0])
    with pytest.raises(InputError, match=r"takes integers, got 3\.33"):
        plan(_study(tmp_path, REDUCED.format(axes="bristles = { linspace = [2, 6, 4] }")))


@settings(max_examples=20)
@given(n=st.integers(1, 60), seed=st.integers(0, 2**31))
def test_latin_hypercube_puts_one_sample_in_each_stratum(tmp_path_factory, n, seed):
    tmp = tmp_path_factory.mktemp("lhs")
    axes = "s_max = { lhs = [2.0, 12.0] }\nfp = { lhs = [0.1, 0.3] }\nk = { random = [0.4, 0.6] }"
    p = plan(_study(tmp, f"samples = {n}\nseed = {seed}\n" + REDUCED.format(axes=axes)))
    assert p.designs.dims == (("sample", n),)
    for key, (lo, hi) in {"s_max": (2.0, 12.0), "fp": (0.1, 0.3)}.items():
        u = (p.designs.values[key] - lo) / (hi - lo)
        np.testing.assert_array_equal(np.sort(np.floor(u * n)), np.arange(n))
    k = p.designs.values["k"]
    assert np.all((k >= 0.4) & (k <= 0.6))


def test_the_shipped_studies_are_valid():
    assert {"inclination", "bristles", "texture", "stroke"} <= set(available_studies())
    sizes = {name: plan(name).designs.n for name in ("inclination", "bristles", "texture")}
    assert sizes == {"inclination": 6, "bristles": 10, "texture": 12}
    assert plan("inclination").base.config["actuation"]["cycles"] == 2


@pytest.mark.parametrize(
    ("axes", "words"),
    [
        ('"bristle.alpa_deg" = [10.0]', "unknown scenario key"),
        ('"bristle" = [10.0]', "a section, not a value"),
        ('"bristle.alpha_deg" = []', "empty list"),
        ('"bristle.alpha_deg" = { linspace = [0.0, 30.0, 0] }', "empty range"),
        ('"bristle.alpha_deg" = { linspace = [10.0, 10.0, 3] }', "empty range"),
        ('"contact.mu" = { random = [0.9, 0.3] }', "empty or inverted range"),
        ('"contact.mu" = { logspace = [0.0, 1.0, 3] }', "positive bounds"),
        (
            '"bristle.alpha_deg" = [30.0, 85.0]',
            "design 1 (bristle.alpha_deg=85): bristle.alpha_deg: must be < 80, got 85",
        ),
        (
            '"actuation.s_max" = [20.0, 120.0]',
            "design 1 (actuation.s_max=120): actuation.s_max (120 mm) must be smaller",
        ),
    ],
)
def test_bad_fe_study_is_one_line_exit_2_and_writes_nothing(tmp_path, run_cli, axes, words):
    study = _study(tmp_path, f'model = "fe"\nbase = "paper"\n[axes]\n{axes}\n')
    out = tmp_path / "out"
    code, _, err = run_cli(["sweep", study, "--out", str(out)])
    assert code == 2
    assert err.startswith("error: ") and err.count("\n") == 1
    assert words in err
    assert not out.exists()


@pytest.mark.parametrize(
    ("axes", "words"),
    [
        ("alpha = [1.0]", "unknown key of the reduced model"),
        ("s_max = [10.0, 150.0]", "design 1 (s_max=150): s_max (150 mm) must be smaller"),
        ("fp = [0.2, -1.0]", "design 1 (fp=-1): fp: must be >= 1e-09, got -1"),
        ('gait = ["breathing", "crawl"]', "design 1 (gait=crawl): gait: Input should be"),
    ],
)
def test_bad_reduced_study_names_the_design(tmp_path, run_cli, axes, words):
    study = _study(tmp_path, REDUCED.format(axes=axes))
    code, _, err = run_cli(["sweep", study, "--out", str(tmp_path / "out")])
    assert (code, err.count("\n")) == (2, 1)
    assert words in err
    assert not (tmp_path / "out").exists()


def test_large_reduced_study_is_checked_in_bulk_and_names_the_design(tmp_path):
    axes = "s_max = { linspace = [1.0, 100.0, 300] }\nfp = { linspace = [0.1, 1.0, 100] }"
    with pytest.raises(InputError, match=r"design 29900 \(s_max=100, fp=0.1\): s_max \(100 mm\)"):
        plan(_study(tmp_path, REDUCED.format(axes=axes)))


def test_unreachable_scheduler_is_refused_before_anything_is_written(tmp_path):
    import socket

    with socket.socket() as s:  # a port nobody listens on
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    study = _study(tmp_path, REDUCED.format(axes="s_max = [10.0]"))
    address = f"tcp://127.0.0.1:{port}"
    options = SweepOptions(out=tmp_path / "out", scheduler=address, connect_timeout_s=2.0)
    with pytest.raises(InputError, match=f"cannot reach the Dask scheduler at {address} within"):
        run_sweep(study, options)
    assert not (tmp_path / "out").exists()


def test_a_folder_with_another_study_is_refused_and_left_as_it_was(tmp_path, run_cli):
    out = tmp_path / "out"
    out.mkdir()
    held = {"fingerprint": "0123456789abcdef", "study": {"name": "other"}}
    (out / "study.json").write_text(json.dumps(held))
    study = _study(tmp_path, REDUCED.format(axes="s_max = [10.0]"))
    for extra in ([], ["--resume"]):
        code, _, err = run_cli(["sweep", study, "--out", str(out), *extra])
        assert code == 2 and "holds another study's results ('other')" in err
    assert sorted(p.name for p in out.iterdir()) == ["study.json"]
    assert json.loads((out / "study.json").read_text()) == held
    code, _, err = run_cli(["sweep", study, "--resume"])
    assert code == 2 and "--resume needs --out" in err


def test_batches_group_the_designs_of_one_structure(tmp_path):
    """--batch B: one task per batch of up to B designs of one structure (here the
    bristle count splits them), each task B designs wide."""
    from bristlecrawler.studies.runner import batch_tasks

    axes = '"bristle.count" = [2, 3]\n"bristle.alpha_deg" = [30.0, 40.0, 50.0]'
    p = plan(_study(tmp_path, f'model = "fe"\nbase = "paper"\n[axes]\n{axes}\n'))
    tasks = batch_tasks(p, 2)
    assert [t.index.tolist() for t in tasks] == [[0, 1], [2], [3, 4], [5]]
    assert {t.args[2] for t in tasks} == {2}


@pytest.mark.parametrize(
    ("study_text", "flag", "words"),
    [
        (
            'model = "fe"\nbase = "paper"\n[axes]\n"bristle.alpha_deg" = [30.0, 40.0]\n',
            "3",
            "batch size 3 is larger than the 2 designs given",
        ),
        (
            'model = "fe"\nbase = "paper"\n[axes]\n"bristle.alpha_deg" = [30.0, 40.0]\n',
            "0",
            "--batch must be a whole number >= 1",
        ),
        (REDUCED.format(axes="s_max = [10.0, 20.0]"), "2", "this study is of the reduced model"),
    ],
)
def test_a_bad_batch_is_one_line_exit_2_and_writes_nothing(
    tmp_path, run_cli, study_text, flag, words
):
    out = tmp_path / "out"
    code, _, err = run_cli(
        ["sweep", _study(tmp_path, study_text), "--out", str(out), "--batch", flag]
    )
    assert code == 2
    assert err.startswith("error: ") and err.count("\n") == 1
    assert words in err
    assert not out.exists()


FE_MU = """
name = "mu"
model = "fe"
base = "paper"
[set]
{set}
[axes]
"bristle.alpha_deg" = [30.0, 45.0]
{axes}
"""


def test_the_old_key_substrate_mu_in_a_study_reads_as_contact_mu(tmp_path):
    """A study's ``substrate.mu`` ([set] or [axes]) is ``contact.mu``, with a warning line:
    the same designs and resolved study (fingerprint included); a design's overrides with
    the old key give the same scenario."""
    from bristlecrawler.scenario.load import DeprecatedKeyWarning
    from bristlecrawler.studies.designs import with_overrides

    def both(set_text, axes_text):
        new = plan(_study(tmp_path, FE_MU.format(set=set_text, axes=axes_text), "new.toml"))
        old_text = FE_MU.format(set=set_text, axes=axes_text).replace("contact.mu", "substrate.mu")
        with pytest.warns(DeprecatedKeyWarning, match=r"^substrate\.mu is deprecated: use contact"):
            old = plan(_study(tmp_path, old_text, "old.toml"))
        assert old.resolved == new.resolved
        return old

    old = both("", '"contact.mu" = [0.3, 0.6]')
    assert old.designs.keys == ("bristle.alpha_deg", "contact.mu")
    assert old.designs.overrides(3) == {"bristle.alpha_deg": 45.0, "contact.mu": 0.6}
    old = both('"contact.mu" = 0.5', "")
    assert old.base.config["contact"]["mu"] == 0.5
    config = old.base.config
    with pytest.warns(DeprecatedKeyWarning):
        assert with_overrides(config, {"substrate.mu": 0.3}) == with_overrides(
            config, {"contact.mu": 0.3}
        )
    text = FE_MU.format(set='"substrate.mu" = 0.5', axes='"contact.mu" = [0.3]')
    with pytest.raises(InputError, match=r"contact\.mu: both in \[set\] and in \[axes\]"):
        with pytest.warns(DeprecatedKeyWarning):
            plan(_study(tmp_path, text))
    text = FE_MU.format(set="", axes='"substrate.mu" = [0.5]\n"contact.mu" = [0.3]')
    with pytest.raises(InputError, match=r"\[axes\] give contact\.mu, not both it and substrate"):
        with pytest.warns(DeprecatedKeyWarning):
            plan(_study(tmp_path, text))


@pytest.mark.parametrize("what", ["missing", "fifo", "device", "not json", "no law"])
@pytest.mark.parametrize("where", ["set", "axis"])
def test_a_texture_file_that_cannot_be_used_is_refused_before_any_design(
    tmp_path, run_cli, what, where
):
    """Every design's texture file is read and checked up front: one line, exit 2, no
    design run and nothing written (not a study whose every design failed)."""
    import os

    from bristlecrawler.results.texture import TextureLaw

    good = tmp_path / "good.json"
    good.write_text(json.dumps({"texture": TextureLaw.constant(0.4, 1.2, 0.5).to_dict()}))
    bad = tmp_path / "bad.json"
    if what == "fifo":
        os.mkfifo(bad)
    elif what == "device":
        bad = "/dev/zero"
    elif what == "not json":
        bad.write_text("{")
    elif what == "no law":
        bad.write_text("[1, 2]")
    if where == "set":
        text = REDUCED.format(axes="s_max = [5.0, 10.0]").replace(
            "cycles = 3", f"cycles = 3\ntexture = {json.dumps(str(bad))}"
        )
    else:
        text = REDUCED.format(axes=f"texture = {json.dumps([str(good), str(bad)])}")
    with pytest.raises(InputError, match="texture"):
        plan(_study(tmp_path, text))
    out = tmp_path / "out"
    code, stdout, err = run_cli(["sweep", _study(tmp_path, text), "--out", str(out)])
    assert code == 2 and stdout == "" and err.count("\n") == 1 and "texture" in err
    assert not out.exists()


def test_a_history_file_that_is_missing_is_refused_before_any_design(tmp_path):
    text = REDUCED.format(axes="s_max = [5.0, 10.0]").replace(
        "cycles = 3", f"cycles = 3\nhistory = {json.dumps(str(tmp_path / 'none.csv'))}"
    )
    with pytest.raises(InputError, match="history file not found"):
        plan(_study(tmp_path, text))


@pytest.mark.parametrize("value", ["3", "[1, 2]", '"x"'])
def test_a_reduced_base_whose_table_is_not_a_table_is_one_line(tmp_path, value):
    (tmp_path / "base.toml").write_text(f"reduced = {value}\n")
    text = REDUCED.format(axes="s_max = [5.0, 10.0]")
    with pytest.raises(InputError, match=r"\[reduced\] must be a table"):
        plan(_study(tmp_path, 'base = "base.toml"\n' + text))


def test_a_reduced_design_past_the_cost_bound_is_refused_before_any_design(tmp_path):
    text = REDUCED.format(axes="bristles = [2, 10000]").replace(
        "cycles = 3", "cycles = 3\ns_max = 0.5\nlength = 10000.0"
    )
    with pytest.raises(InputError, match=r"10,000 bristles.*CPU time"):
        plan(_study(tmp_path, text))
