"""Scenario files that start from a shipped one, and the `bristlecrawler scenario` command."""

import json
import math

import pytest

from bristlecrawler.errors import InputError
from bristlecrawler.scenario import Scenario, load_scenario, scenario_from_dict
from bristlecrawler.scenario.keys import NA, differs, scenario_keys


def _flat(d, prefix=""):
    out = {}
    for k, v in d.items():
        if isinstance(v, dict):
            out |= _flat(v, f"{prefix}{k}.")
        else:
            out[f"{prefix}{k}"] = v
    return out


def test_a_file_with_base_paper_changes_only_what_it_sets(tmp_path):
    f = tmp_path / "tilted.toml"
    f.write_text('base = "paper"\n[bristle]\nalpha_deg = 30.0\n')
    sc, paper = load_scenario(f), load_scenario("paper")
    a, b = _flat(sc.model_dump()), _flat(paper.model_dump())
    changed = {k for k in a if a[k] != b[k]}
    assert changed == {"bristle.alpha_deg", "name", "description"}
    assert sc.bristle.alpha_deg == 30.0 and sc.name == "tilted"
    # the values in which paper departs from the schema's defaults are inherited
    assert sc.substrate.fillet_top == 0.02
    assert sc.contact.stick_drift == 1e-3
    assert math.isinf(sc.solver.energy_loss_tol)


def test_without_base_the_defaults_apply_and_the_keys_table_says_where_paper_differs(tmp_path):
    f = tmp_path / "plain.toml"
    f.write_text("[bristle]\nalpha_deg = 30.0\n")
    sc = load_scenario(f)
    paper = _flat(load_scenario("paper").model_dump())
    plain = _flat(sc.model_dump())
    flagged = {k.key for k in scenario_keys() if differs(k)}
    # every physical or numerical value in which a bare file differs from paper is flagged
    differ = {k for k in plain if plain[k] != paper[k]} - {"bristle.alpha_deg", "name"}
    differ -= {"description"}
    assert differ and differ <= flagged
    assert {"substrate.fillet_top", "contact.stick_drift", "solver.energy_loss_tol"} <= flagged


def test_another_substrate_kind_replaces_the_base_table(tmp_path):
    f = tmp_path / "teeth.toml"
    f.write_text('base = "paper"\n[substrate]\nkind = "sawtooth"\npitch = 2.0\nheight = 0.3\n')
    sc = load_scenario(f)
    assert sc.substrate.kind == "sawtooth" and sc.contact.mu == 0.65


def test_a_base_can_be_another_file_relative_to_the_first(tmp_path):
    (tmp_path / "sub").mkdir()
    (tmp_path / "sub" / "a.toml").write_text('base = "paper"\n[actuation]\ncycles = 2\n')
    (tmp_path / "b.toml").write_text('base = "sub/a.toml"\n[bristle]\nelements = 10\n')
    sc = load_scenario(tmp_path / "b.toml")
    assert (sc.actuation.cycles, sc.bristle.elements, sc.bristle.alpha_deg) == (2, 10, 45.0)


@pytest.mark.parametrize(
    "text, words",
    [
        ('base = "a.toml"\n', "longer than"),  # the file names itself
        ('base = "nope"\n', "unknown scenario 'nope'"),
        ("base = 3\n", "base must be"),
        ('base = "paper"\n[bristle]\nalpha = 3.0\n', "alpha"),
    ],
)
def test_bad_bases_are_one_line_errors(tmp_path, run_cli, text, words):
    f = tmp_path / "a.toml"
    f.write_text(text)
    with pytest.raises(InputError, match=words):
        load_scenario(f)
    code, out, err = run_cli(["scenario", "show", str(f)])
    assert code == 2 and out == "" and err.startswith("error: ") and err.count("\n") == 1


@pytest.mark.parametrize("name", ["paper", "paper-vertical"])
def test_show_resolved_loads_back_to_the_same_scenario(tmp_path, run_cli, name):
    code, out, _ = run_cli(["scenario", "show", name, "--resolved"])
    assert code == 0
    f = tmp_path / "again.toml"
    f.write_text(out)
    assert load_scenario(f) == load_scenario(name)


def test_show_prints_the_shipped_file_with_its_comments(run_cli):
    code, out, _ = run_cli(["scenario", "show", "paper"])
    assert code == 0 and out.startswith("# Noselli & DeSimone")
    assert "energy_loss_tol = inf" in out


def test_keys_cover_every_value_of_a_scenario_with_units(run_cli):
    code, out, _ = run_cli(["scenario", "keys", "--json"])
    assert code == 0
    rows = json.loads(out)
    grooves = {r["key"] for r in rows if r["substrate_kind"] in (None, "grooves")}
    assert grooves == set(_flat(Scenario().model_dump()))
    for key in scenario_keys():
        assert key.meaning, key.key
        if key.type == "float":  # every float is a physical or numerical quantity
            assert key.unit, f"{key.key}: no unit in its description"
        if key.paper is not NA and not key.required:
            assert isinstance(differs(key), bool)


def test_keys_markdown_has_a_row_per_key(run_cli):
    code, out, _ = run_cli(["scenario", "keys", "--markdown"])
    assert code == 0
    rows = [line for line in out.splitlines() if line.startswith("| `")]
    assert len(rows) == len(scenario_keys())
    assert "| `fillet_top` | float | mm | `0.0` | **`0.02`** |" in out


def test_a_folder_named_like_a_shipped_scenario_does_not_hide_it(tmp_path, monkeypatch):
    """`simulate paper --out paper`, then `simulate paper` again: the run folder is not a
    scenario file."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "paper").mkdir()
    assert load_scenario("paper").name == "paper"


def test_set_substrate_kind_starts_that_table_afresh():
    from bristlecrawler.scenario.load import apply_overrides

    paper = load_scenario("paper")
    sc = apply_overrides(
        paper, ["substrate.kind=sawtooth", "substrate.pitch=2.5", "substrate.height=0.3"]
    )
    assert (sc.substrate.kind, sc.substrate.pitch, sc.substrate.height) == ("sawtooth", 2.5, 0.3)
    assert sc.contact.mu == paper.contact.mu
    with pytest.raises(InputError, match=r"substrate\.pitch"):
        apply_overrides(paper, ["substrate.kind=sawtooth", "substrate.height=0.3"])
    with pytest.raises(InputError, match="widht"):
        apply_overrides(paper, ["substrate.widht=0.3"])


def test_a_file_without_base_is_told_which_paper_values_it_misses(tmp_path):
    from bristlecrawler.scenario.keys import defaults_unlike_paper
    from bristlecrawler.scenario.load import scenario_document

    plain = tmp_path / "plain.toml"
    plain.write_text("[bristle]\nalpha_deg = 30.0\n[contact]\nstick_drift = 1e-3\n")
    missed = {k.key for k in defaults_unlike_paper(scenario_document(plain))}
    assert missed == {"substrate.fillet_top", "solver.energy_loss_tol"}
    based = tmp_path / "based.toml"
    based.write_text('base = "paper"\n[bristle]\nalpha_deg = 30.0\n')
    assert defaults_unlike_paper(scenario_document(based)) == []
    sharp = tmp_path / "flat.toml"
    sharp.write_text('[substrate]\nkind = "flat"\n')
    assert "substrate.fillet_top" not in {
        k.key for k in defaults_unlike_paper(scenario_document(sharp))
    }


def test_the_friction_coefficient_is_a_contact_key(run_cli):
    code, out, _ = run_cli(["scenario", "keys", "--json"])
    keys = {r["key"] for r in json.loads(out)}
    assert code == 0 and "contact.mu" in keys and "substrate.mu" not in keys
    code, out, _ = run_cli(["scenario", "show", "paper", "--resolved"])
    contact = out.split("[contact]\n")[1].split("\n\n")[0]
    assert code == 0 and "mu = 0.65" in contact.splitlines()
    with pytest.raises(InputError, match=r"contact\.mu: must be <= 10, got 11"):
        scenario_from_dict({"contact": {"mu": 11.0}})


def test_the_old_key_substrate_mu_in_a_file_reads_as_contact_mu(tmp_path, run_cli):
    """``[substrate] mu`` gives the spec of ``[contact] mu``, with one warning line naming
    the new key; in a file it overrides its base's ``contact.mu``."""
    from bristlecrawler.scenario.convert import to_spec
    from bristlecrawler.scenario.load import DeprecatedKeyWarning

    (tmp_path / "new.toml").write_text('base = "paper"\nname = "s"\n[contact]\nmu = 0.3\n')
    old = tmp_path / "old.toml"
    old.write_text('base = "paper"\nname = "s"\n[substrate]\nmu = 0.3\n')
    with pytest.warns(
        DeprecatedKeyWarning, match=r"^substrate\.mu is deprecated: use contact\.mu$"
    ):
        sc = load_scenario(old)
    assert sc.contact.mu == 0.3
    assert to_spec(sc) == to_spec(load_scenario(tmp_path / "new.toml"))
    # the old key over a base's new one; another substrate kind over a base's old one
    (tmp_path / "over.toml").write_text('base = "new.toml"\n[substrate]\nmu = 0.4\n')
    (tmp_path / "teeth.toml").write_text(
        'base = "old.toml"\n[substrate]\nkind = "sawtooth"\npitch = 2.0\nheight = 0.3\n'
    )
    with pytest.warns(DeprecatedKeyWarning):
        assert load_scenario(tmp_path / "over.toml").contact.mu == 0.4
        assert load_scenario(tmp_path / "teeth.toml").contact.mu == 0.3
    code, out, err = run_cli(["scenario", "show", str(old), "--resolved"])
    assert code == 0 and "mu = 0.3" in out.split("[contact]\n")[1].splitlines()
    assert "mu" not in out.split("[substrate]\n")[1].split("\n\n")[0]
    assert err == "warning: substrate.mu is deprecated: use contact.mu\n"
    both = tmp_path / "both.toml"
    both.write_text("[substrate]\nmu = 0.3\n[contact]\nmu = 0.4\n")
    with pytest.raises(InputError, match=r"give contact\.mu, not both it and substrate\.mu"):
        with pytest.warns(DeprecatedKeyWarning):
            load_scenario(both)


def test_the_old_key_substrate_mu_in_set_reads_as_contact_mu():
    from bristlecrawler.scenario.convert import to_spec
    from bristlecrawler.scenario.load import DeprecatedKeyWarning, apply_overrides, apply_values

    paper = load_scenario("paper")
    new = to_spec(apply_overrides(paper, ["contact.mu=0.3"]))
    with pytest.warns(
        DeprecatedKeyWarning, match=r"^substrate\.mu is deprecated: use contact\.mu$"
    ):
        assert to_spec(apply_overrides(paper, ["substrate.mu=0.3"])) == new
    with pytest.warns(DeprecatedKeyWarning):
        assert to_spec(apply_values(paper, {"substrate.mu": 0.3})) == new
        assert scenario_from_dict({"substrate": {"kind": "flat", "mu": 0.3}}).contact.mu == 0.3
    with pytest.raises(InputError, match=r"give contact\.mu, not both it and substrate\.mu"):
        with pytest.warns(DeprecatedKeyWarning):
            apply_overrides(paper, ["substrate.mu=0.3", "contact.mu=0.4"])
