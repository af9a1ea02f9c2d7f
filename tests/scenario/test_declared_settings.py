"""Every setting declared once (name, default, meaning with its unit, range, whether it is
structural) on the spec's dataclasses; the scenario tables, the ``scenario keys`` listing
and the batch's structure keys are generated from the declarations, and every rule
between settings is the spec's own ``check``."""

import dataclasses
import math

import pytest

from bristlecrawler import fe
from bristlecrawler.crawler import Actuation, Body, Bristle, Contact, CrawlerSpec, Damping, Solver
from bristlecrawler.crawler.structure import STRUCTURE_KEYS
from bristlecrawler.errors import InputError
from bristlecrawler.fe.hht import HHT
from bristlecrawler.fe.options import own_defaults, settings_of
from bristlecrawler.scenario import load_scenario, scenario_from_dict, to_spec
from bristlecrawler.scenario.keys import scenario_keys
from bristlecrawler.scenario.substrate import KINDS, parse_substrate

SECTIONS = {
    "body": Body,
    "bristle": Bristle,
    "contact": Contact,
    "damping": Damping,
    "actuation": Actuation,
    "solver": Solver,
}


def test_each_section_lists_exactly_its_declared_settings_with_their_defaults():
    keys = {k.key: k for k in scenario_keys()}
    for section, cls in SECTIONS.items():
        for f in settings_of(cls):
            key = keys[f"{section}.{f.name}"]
            assert key.default == f.default, key.key
            assert key.structural is f.metadata["structural"], key.key
            assert key.meaning, key.key
    scenario_only = {"bristle.count", "actuation.kind", "actuation.history"}
    declared = {f"{s}.{f.name}" for s, c in SECTIONS.items() for f in settings_of(c)}
    in_sections = {k for k in keys if k.split(".")[0] in SECTIONS}
    assert in_sections == declared | scenario_only


def test_each_substrate_kind_lists_its_declared_settings():
    keys = scenario_keys()
    for kind, settings in KINDS.items():
        listed = {k.key.split(".")[1] for k in keys if k.kind == kind}
        assert listed == {f.name for f in settings_of(settings)}, kind


def test_the_structure_keys_are_the_settings_declared_structural():
    flagged = {k.key for k in scenario_keys() if k.structural}
    spec_keys = {k for k in STRUCTURE_KEYS if "." in k}
    assert spec_keys == flagged - {"bristle.count", "actuation.kind", "substrate.kind"}
    assert "bristle.elements" in spec_keys and "bristle.alpha_deg" not in spec_keys
    assert "solver.dt_max" not in spec_keys and "solver.tolerance" in spec_keys


def test_a_tip_thicker_than_its_clamp_is_refused_by_the_python_api():
    spec = CrawlerSpec.paper().replace_bristles(thickness_tip=3.5)
    with pytest.raises(InputError) as err:
        spec.check()
    assert str(err.value) == (
        "bristles[0].thickness_tip (3.5 mm) must not exceed bristles[0].thickness_clamp "
        "(3 mm): the bristle tapers from its clamp"
    )
    CrawlerSpec.paper().replace_bristles(thickness_tip=3.0).check()  # a prism is fine


def test_a_tip_thicker_than_its_clamp_is_refused_in_a_scenario_file(tmp_path, run_cli):
    f = tmp_path / "thick.toml"
    f.write_text('base = "paper"\n[bristle]\nthickness_tip = 3.5\n')
    code, out, err = run_cli(["simulate", str(f)])
    assert code == 2 and out == ""
    assert err == (
        f"error: {f}: bristle.thickness_tip (3.5 mm) must not exceed "
        "bristle.thickness_clamp (3 mm): the bristle tapers from its clamp\n"
    )


@pytest.mark.parametrize(
    ("change", "words"),
    [
        ({"bristle": {"poisson_ratio": 0.5}}, "poisson_ratio"),
        ({"damping": {"ratio": 1.0}}, "damping.ratio"),
        ({"contact": {"nodes": "some"}}, "contact.nodes"),
        ({"body": {"mass": 2.0}}, "body.mass"),
        ({"actuation": {"lag": -1.0}}, "actuation.lag"),
        ({"gravity": 0.0}, "gravity = 0 leaves no weight"),
        ({"actuation": {"s_max": 100.0}}, "smaller than the body length"),
    ],
)
def test_the_python_api_and_the_scenario_refuse_the_same_designs(change, words):
    """One declaration, one rule: a value the scenario refuses, the spec refuses too."""
    with pytest.raises(InputError, match=words):
        scenario_from_dict(change)
    spec = to_spec(load_scenario("paper"))
    for section, values in change.items():
        if section == "gravity":
            spec = dataclasses.replace(spec, gravity=values)
        elif section == "bristle":
            spec = spec.replace_bristles(**values)
        else:
            part = dataclasses.replace(getattr(spec, section), **values)
            spec = dataclasses.replace(spec, **{section: part})
    with pytest.raises(InputError, match=words.split(".")[-1]):
        spec.check()


def test_a_substrate_rule_is_the_substrate_s_own():
    """Width beyond the pitch: the grooves' constructor says so, once, in one line."""
    with pytest.raises(InputError) as err:
        parse_substrate({"kind": "grooves", "width": 3.0, "depth": 0.25, "pitch": 2.0})
    with pytest.raises(InputError) as direct:
        KINDS["grooves"](width=3.0, depth=0.25, pitch=2.0)
    assert str(err.value) == str(direct.value) and "pitch" in str(err.value)


def test_the_solver_defaults_that_differ_from_the_fe_core_are_declared_with_a_reason():
    """Where the crawler's [solver] default is not NewtonOptions' or StepControl's own,
    the declaration says so and why; nowhere else do they differ."""
    fe_defaults = {**dataclasses.asdict(fe.NewtonOptions()), **dataclasses.asdict(fe.StepControl())}
    solver = Solver()
    differ = {
        f.name
        for f in dataclasses.fields(Solver)
        if f.name in fe_defaults and getattr(solver, f.name) != fe_defaults[f.name]
    }
    declared = own_defaults(Solver)
    assert (
        differ == set(declared) == {"tolerance", "max_iterations", "line_search", "max_correction"}
    )
    for name, (ours, theirs, why) in declared.items():
        assert ours == getattr(solver, name) and theirs == fe_defaults[name] and why
    assert (declared["tolerance"][:2], declared["max_iterations"][:2]) == ((1e-8, 1e-9), (25, 12))


def _lower(bounds):
    return max(bounds.get("ge", -math.inf), bounds.get("gt", -math.inf))


def _upper(bounds):
    return min(bounds.get("le", math.inf), bounds.get("lt", math.inf))


def test_the_solver_ranges_lie_within_the_fe_core_ranges():
    """The crawler narrows a setting's range, never widens it: a value the [solver] table
    takes, HHT, NewtonOptions and StepControl take too."""
    owners = (HHT, fe.NewtonOptions, fe.StepControl)
    fe_settings = {f.name: f for c in owners for f in settings_of(c)}
    fe_settings["hht_alpha"] = fe_settings["alpha"]
    shared = [f for f in settings_of(Solver) if f.name in fe_settings]
    assert len(shared) == 10
    for f in shared:
        ours, theirs = f.metadata["bounds"], fe_settings[f.name].metadata["bounds"]
        assert _lower(ours) >= _lower(theirs) and _upper(ours) <= _upper(theirs), f.name
        assert f.metadata["inf"] <= fe_settings[f.name].metadata["inf"], f.name


def test_a_substrate_setting_out_of_its_range_says_so_as_every_other_key(tmp_path, run_cli):
    code, _, err = run_cli(["simulate", "paper", "--set", "substrate.phase=1e308"])
    assert code == 2 and err == (
        "error: scenario (with --set): substrate.phase: must be <= 10000, got 1e+308 "
        "(x of a groove's left wall, mm)\n"
    )


def test_the_solver_scheme_chooses_the_integrator_with_the_scenarios_newton_settings():
    """``solver.scheme`` reaches the kernels: backward Euler with the scenario's Newton
    settings and predictor (HHT's alpha left out), HHT with ``hht_alpha``; a word that
    names no scheme is refused in one line."""
    from bristlecrawler.scenario.load import apply_overrides

    be = to_spec(apply_overrides(load_scenario("paper"), ['solver.scheme="backward_euler"']))
    hht = to_spec(apply_overrides(load_scenario("paper"), ["solver.hht_alpha=-0.2"]))
    ig_be, ig_hht = be.solver.integrator(1e-3), hht.solver.integrator(1e-3)
    assert isinstance(ig_be, fe.BackwardEuler) and isinstance(ig_hht, fe.HHT)
    assert ig_be.newton == be.solver.newton and ig_be.predictor == be.solver.predictor
    assert ig_be.penetration_limit == 1e-3
    assert ig_hht.alpha == -0.2
    assert "solver.scheme" in STRUCTURE_KEYS
    with pytest.raises(InputError, match=r"solver\.scheme"):
        apply_overrides(load_scenario("paper"), ['solver.scheme="euler"'])
    with pytest.raises(InputError, match="hht_alpha is HHT's"):
        apply_overrides(
            load_scenario("paper"), ['solver.scheme="backward_euler"', "solver.hht_alpha=-0.2"]
        )
