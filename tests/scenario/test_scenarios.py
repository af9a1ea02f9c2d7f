"""Shipped scenarios and scenario validation (one-line errors naming the field)."""

import math

import pytest

from bristlecrawler.errors import InputError
from bristlecrawler.scenario import available_scenarios, load_scenario, scenario_from_dict


def test_shipped_scenarios_hold_the_paper_values():
    assert {"paper", "paper-vertical"} <= set(available_scenarios())
    p = load_scenario("paper")
    assert p.bristle.alpha_deg == pytest.approx(math.degrees(math.pi / 4))
    assert (p.body.length, p.body.mass) == (100.0, pytest.approx(5.5e-5))
    assert (p.bristle.thickness_clamp, p.bristle.thickness_tip, p.bristle.length) == (3, 0.5, 5)
    assert p.bristle.youngs_modulus == 1.1 and p.bristle.density == pytest.approx(1.3e-9)
    assert (p.substrate.width, p.substrate.depth, p.contact.mu) == (1.0, 0.25, 0.65)
    assert (p.actuation.s_max, p.actuation.period, p.actuation.cycles) == (20.0, 20.0, 5)
    assert p.damping.ratio == 0.15 and p.damping.kind == "mass"
    v = load_scenario("paper-vertical")
    assert v.bristle.alpha_deg == 0.0
    # The same model; only two numerical settings differ. The bound on the energy a step
    # may lose: the paper run takes its snaps in large steps, the vertical bristles' flips
    # are resolved. The stick penalty: the paper run allows ten times the elastic slip.
    skip = {"name": True, "description": True, "bristle": True}
    skip["solver"] = {"energy_loss_tol"}
    skip["contact"] = {"stick_drift"}
    assert v.model_dump(exclude=skip) == p.model_dump(exclude=skip)
    assert p.solver.energy_loss_tol == math.inf
    assert math.isfinite(v.solver.energy_loss_tol)
    assert p.contact.stick_drift == pytest.approx(10 * v.contact.stick_drift)


@pytest.mark.parametrize(
    ("data", "word"),
    [
        ({"bristle": {"alpha_deg": 80}}, "alpha_deg"),
        ({"bristle": {"alpha_deg": -95}}, "alpha_deg"),
        ({"actuation": {"s_max": 100}}, "s_max"),
        ({"bristle": {"youngs_modulus": 0}}, "youngs_modulus"),
        ({"bristle": {"thickness_tip": -1}}, "thickness_tip"),
        ({"body": {"length": -5}}, "length"),
        ({"actuation": {"kind": "history"}}, "history"),
        ({"substrate": {"kind": "grooves", "width": 1, "depth": 0, "pitch": 2}}, "depth"),
        ({"solver": {"max_correction": 0}}, "max_correction"),
        ({"bristel": {}}, "bristel"),
    ],
)
def test_bad_scenarios(data, word):
    with pytest.raises(InputError, match=word) as err:
        scenario_from_dict(data)
    assert "\n" not in str(err.value)


def test_files_and_unknown_names(tmp_path):
    f = tmp_path / "s.toml"
    f.write_text(
        'name = "mine"\n[bristle]\nalpha_deg = 30.0\n[actuation]\nkind = "history"\n'
        'history = "h.csv"\n'
    )
    s = load_scenario(f)
    assert s.bristle.alpha_deg == 30.0 and s.actuation.history == str(tmp_path / "h.csv")
    with pytest.raises(InputError, match="unknown scenario 'papr'"):
        load_scenario("papr")
    bad = tmp_path / "bad.toml"
    bad.write_text("[bristle\n")
    with pytest.raises(InputError, match="invalid TOML"):
        load_scenario(bad)
    with pytest.raises(InputError, match="not found"):
        load_scenario(tmp_path / "none.toml")
