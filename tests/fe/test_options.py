"""One name, one default and one range per solver setting: the crawler's ``Solver``
declares them, the scenario table is built from them, and the FE kernels' option objects
take them under the same names (the old names still work, with a DeprecationWarning)."""

import dataclasses
import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from bristlecrawler import fe
from bristlecrawler.crawler import Solver
from bristlecrawler.errors import InputError
from bristlecrawler.scenario import load_scenario
from bristlecrawler.scenario.convert import to_spec
from bristlecrawler.scenario.keys import scenario_keys
from bristlecrawler.scenario.load import apply_overrides, scenario_from_dict
from bristlecrawler.scenario.schema import SolverConfig

BOUNDED = [f for f in dataclasses.fields(Solver) if f.metadata["bounds"]]


def test_every_solver_setting_is_a_scenario_key_with_its_default():
    keys = {k.key: k for k in scenario_keys() if k.key.startswith("solver.")}
    for f in dataclasses.fields(Solver):
        assert f"solver.{f.name}" in keys, f.name
        assert keys[f"solver.{f.name}"].default == f.default
    assert set(keys) == {f"solver.{f.name}" for f in dataclasses.fields(Solver)}


def test_step_control_settings_reach_the_runs_step_rule_from_a_file():
    sc = apply_overrides(load_scenario("paper"), ["solver.grow=2.0", "solver.easy_iterations=7"])
    control = to_spec(sc).solver.control
    assert (control.grow, control.easy_iterations) == (2.0, 7)


@settings(max_examples=40, deadline=None)
@given(field=st.sampled_from(BOUNDED), side=st.sampled_from(["below", "above"]))
def test_a_setting_outside_its_range_is_refused_by_the_spec_and_the_file_alike(field, side):
    b = field.metadata["bounds"]
    low = b.get("ge", b.get("gt"))
    if side == "below":
        if low is None:
            return
        bad = low - 1 if isinstance(field.default, int) else low - max(abs(low), 1e-3) * 0.5
        bad = bad if "ge" in b else low
    else:
        if "le" not in b:
            return
        bad = b["le"] + (1 if isinstance(field.default, int) else max(abs(b["le"]), 1.0))
    with pytest.raises(InputError, match=f"solver.{field.name}"):
        Solver(**{field.name: bad}).check()
    with pytest.raises(Exception, match=field.name):
        SolverConfig(**{field.name: bad})


def test_the_rules_between_settings_have_one_home():
    for bad in ({"dt_min": 0.1, "dt_max": 0.05}, {"freeze_iterations": 25}):
        with pytest.raises(InputError) as spec_error:
            Solver(**bad).check()
        with pytest.raises(InputError) as file_error:
            scenario_from_dict({"solver": bad}, origin="file.toml")
        line = f"file.toml: solver: {str(spec_error.value).replace('solver.', '')}"
        assert str(file_error.value) == line


def test_newton_settings_reach_the_kernels_under_their_names():
    sv = Solver(tolerance=1e-9, max_iterations=30, stall_iterations=5, freeze_iterations=3)
    ig = sv.integrator(math.inf)
    for name in ("tolerance", "max_iterations", "stall_iterations", "freeze_iterations"):
        assert getattr(ig.newton, name) == getattr(sv, name)
    assert ig.alpha == sv.hht_alpha and ig.predictor == sv.predictor


def test_old_keyword_names_still_work_with_a_warning():
    with pytest.warns(DeprecationWarning, match="rtol is deprecated: use tolerance"):
        with pytest.warns(DeprecationWarning, match="max_iter is deprecated"):
            old = fe.NewtonOptions(rtol=1e-6, max_iter=7)
    assert old == fe.NewtonOptions(tolerance=1e-6, max_iterations=7)
    with pytest.warns(DeprecationWarning):
        assert old.max_iter == 7
    with pytest.warns(DeprecationWarning):
        ig = fe.Integrator.hht(rtol=1e-12, stall=2)
    assert ig == fe.Integrator.hht(tolerance=1e-12, stall_iterations=2)
    with pytest.warns(DeprecationWarning):
        replaced = dataclasses.replace(fe.NewtonOptions(), freeze=2)
    assert replaced.freeze_iterations == 2


def test_composed_options_take_their_parts_settings_as_keywords():
    opts = fe.StaticOptions(tolerance=1e-12, grow=2.0, increments=3)
    assert opts.newton.tolerance == 1e-12 and opts.newton.max_iterations == 30
    assert opts.control.grow == 2.0 and opts.increments == 3
    with pytest.raises(TypeError, match="unexpected keyword argument 'tolerence'"):
        fe.Integrator.hht(tolerence=1e-9)


def test_the_two_penetrations_have_two_names_and_the_old_key_still_reads(tmp_path):
    """``contact.penetration_limit`` (a step deeper than it is cut) is not the penalty's
    design penetration (``CoulombLaw.for_reference_load(design_penetration=...)``); the
    old key ``contact.max_penetration`` reads as the limit, with a warning line."""
    from bristlecrawler.contact.coulomb import CoulombLaw
    from bristlecrawler.scenario.load import DeprecatedKeyWarning

    with pytest.warns(DeprecatedKeyWarning, match="use contact.penetration_limit"):
        sc = scenario_from_dict({"contact": {"max_penetration": 0.01}})
    assert sc.contact.penetration_limit == 0.01
    with pytest.warns(DeprecatedKeyWarning):
        sc = apply_overrides(load_scenario("paper"), ["contact.max_penetration=0.02"])
    assert to_spec(sc).contact.penetration_limit == 0.02
    assert to_spec(sc).solver.integrator(0.02).penetration_limit == 0.02
    with pytest.raises(InputError, match="not both"), pytest.warns(DeprecatedKeyWarning):
        scenario_from_dict({"contact": {"max_penetration": 0.01, "penetration_limit": 0.02}})
    with pytest.warns(DeprecationWarning, match="design_penetration"):
        old = CoulombLaw.for_reference_load(0.5, load=1.0, max_penetration=1e-4)
    new = CoulombLaw.for_reference_load(0.5, load=1.0, design_penetration=1e-4)
    assert float(old.k_n) == float(new.k_n) == pytest.approx(1e4)
