"""The bristled model: its rod against beam theory, its tip path, and the physics of a run
(energy balance, symmetry, rate independence)."""

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from bristlecrawler.reduced.bristled import (
    BristledDesign,
    Chain,
    GroovedSurface,
    RunOptions,
    TaperedBristle,
    TipPath,
    breathing_fractions,
    elastica_tip,
    play,
    run,
)
from bristlecrawler.reduced.bristled.path import PathTable, disc_shape
from bristlecrawler.reduced.bristled.rod import (
    chain_fields,
    chain_tip_under_force,
    compliance_moment,
)


def _fields(chain: Chain) -> dict:
    return {k: np.asarray(v)[0] for k, v in chain_fields([chain]).items()}


def _tip(chain: Chain, force) -> np.ndarray:
    """Tip from the clamp under a dead tip force (N), body frame, mm."""
    p = _fields(chain)
    joint = chain.s1 * np.array([math.cos(chain.theta_r), math.sin(chain.theta_r)])
    return joint + chain_tip_under_force(np.asarray(force, float), p)


def _transverse_compliance(bristle: TaperedBristle, force: float = 1e-6) -> float:
    """Tip deflection per unit transverse force of the calibrated rod, mm/N."""
    chain = Chain.of(bristle)
    e = np.array([math.cos(chain.theta_r), math.sin(chain.theta_r)])
    n = np.array([-e[1], e[0]])
    moved = _tip(chain, force * n) - chain.rest_tip()
    return float(moved @ n) / force


def test_a_straight_cantilever_has_the_stiffness_3EI_over_L3():
    b = TaperedBristle(thickness_clamp=1.0, thickness_tip=1.0, shear=False)
    EI = b.youngs_modulus * b.width * 1.0**3 / 12.0
    assert 1.0 / _transverse_compliance(b) == pytest.approx(3 * EI / b.length**3, rel=1e-6)


def test_a_tapered_cantilever_has_its_closed_form_compliance():
    """int_0^L (L - s)^2 / EI ds for h = h0 + (h1 - h0) s / L, in closed form:
    12 / (E b c^3) [-h1^2 / (2 h^2) + 2 h1 / h + ln h] from h0 to h1, c = (h1 - h0) / L."""
    b = TaperedBristle(shear=False)
    h0, h1, L = b.thickness_clamp, b.thickness_tip, b.length
    c = (h1 - h0) / L

    def f(h):
        return -(h1**2) / (2 * h**2) + 2 * h1 / h + math.log(h)

    exact = 12.0 / (b.youngs_modulus * b.width * c**3) * (f(h1) - f(h0))
    assert compliance_moment(b, 2) == pytest.approx(exact, rel=1e-10)
    assert _transverse_compliance(b) == pytest.approx(exact, rel=1e-6)


@pytest.mark.parametrize("force", [(0.3, 0.0), (0.0, 0.3), (-0.3, 0.3), (0.2, 0.3)])
def test_the_rod_follows_the_elastica_at_large_deflections(force):
    """Deflections of 0.16-0.7 mm on a 5 mm bristle: the two-joint rod within 2.5 % of
    the exact tapered elastica."""
    b = TaperedBristle(shear=False)
    chain = Chain.of(b)
    exact = elastica_tip(b, force, steps=200)
    moved = exact - chain.rest_tip()
    err = np.linalg.norm(_tip(chain, force) - exact) / np.linalg.norm(moved)
    assert np.linalg.norm(moved) > 0.15
    assert err < 0.025


@given(
    h0=st.floats(0.5, 4.0),
    h1=st.floats(0.2, 2.0),
    length=st.floats(2.0, 10.0),
    alpha=st.floats(-70.0, 70.0),
)
def test_the_rod_has_the_beams_small_deflection_compliance(h0, h1, length, alpha):
    b = TaperedBristle(
        length=length, thickness_clamp=h0, thickness_tip=h1, alpha_deg=alpha, shear=False
    )
    assert _transverse_compliance(b) == pytest.approx(compliance_moment(b, 2), rel=1e-5)


@given(
    pitch=st.floats(1.0, 4.0),
    width_fraction=st.floats(0.2, 0.8),
    depth=st.floats(0.05, 0.5),
    radius=st.floats(0.05, 0.4),
)
def test_a_discs_centre_path_keeps_the_disc_on_the_outline(pitch, width_fraction, depth, radius):
    """Every sampled centre is at least the radius from the outline, and touches it."""
    surface = GroovedSurface(width=width_fraction * pitch, depth=depth, pitch=pitch)
    outline = surface.outline()
    path = TipPath.over(outline, disc_shape(radius), samples=256)
    shift = np.array([pitch, 0.0])
    pts = np.vstack([outline - shift, outline, outline + shift])
    d = np.hypot(path.x[:, None] - pts[None, :, 0], path.y[:, None] - pts[None, :, 1]).min(1)
    assert d.min() > radius - 2e-3
    assert np.median(d) == pytest.approx(radius, abs=2e-3)


def test_the_path_table_folds_whole_pitches():
    path = TipPath.over(GroovedSurface().outline(), disc_shape(0.25), samples=512)
    table = PathTable.of([path])
    u = table.arc_at(0, np.array([0.3, 0.3 + 2.0, 0.3 - 6.0]))
    np.testing.assert_allclose(np.diff(u), [path.length, -4 * path.length])
    centre, _, _ = table.frame(np.zeros(3, int), u)
    np.testing.assert_allclose(centre[:, 0], [0.3, 2.3, -5.7], atol=1e-9)


OPTIONS = RunOptions(ds=0.2)


@pytest.fixture(scope="module")
def paper_cycle():
    return run([BristledDesign.uniform(2, s_max=10.0)], cycles=1, options=OPTIONS)


def test_the_work_is_the_stored_energy_plus_the_dissipation(paper_cycle):
    """W = dE_el + dE_g + D step by step, and W is the actuator's force integrated over
    its shortening (the trapezoid rule's error, under 1 %)."""
    r = paper_cycle
    assert r.ok.all()
    assert abs(r.balance_residual[0]) < 1e-9
    assert r.work[0] == pytest.approx(r.force_work[0], rel=1e-2)
    assert r.dissipation[0] > 0 and r.coulomb[0] > 0
    assert r.net_advance[0] > 0.5 * 10.0


def test_vertical_bristles_do_not_drift():
    """alpha = 0 and each tip in the middle of a groove: the crawler is its own mirror
    image and the stroke its own, so it goes nowhere."""
    d = BristledDesign.uniform(2, bristle=TaperedBristle(alpha_deg=0.0), s_max=6.0, start=0.5)
    r = run([d], cycles=1, options=OPTIONS)
    assert r.ok.all()
    assert abs(r.net_advance[0]) < 1e-3


def test_a_batch_gives_what_each_design_gives_alone():
    """Designs whose tips slide and snap at different steps: each design's run in the
    batch is its run alone."""
    designs = [
        BristledDesign.uniform(2, s_max=6.0),
        BristledDesign.uniform(2, s_max=6.0, surface=GroovedSurface(pitch=3.0)),
        BristledDesign.uniform(
            2, bristle=TaperedBristle(alpha_deg=30.0), s_max=6.0, surface=GroovedSurface(pitch=1.5)
        ),
    ]
    both = run(designs, cycles=1, options=OPTIONS)
    for k, design in enumerate(designs):
        alone = run([design], cycles=1, options=OPTIONS)
        np.testing.assert_allclose(both.front[k], alone.front[0], rtol=0, atol=1e-12)
        for name in ("work", "dissipation", "coulomb", "elastic", "gravity"):
            assert getattr(both, name)[k] == pytest.approx(getattr(alone, name)[0], rel=1e-12)
        for name in ("lifts", "unconverged", "stalled"):
            assert getattr(both, name)[k] == getattr(alone, name)[0]
    assert both.ok.all()


def test_holding_the_shortening_still_changes_nothing():
    """Rate independence: the same values of s with each one held for a second step (time
    passing, s standing still) give the same run: no creep, no work, no dissipation."""
    design = [BristledDesign.uniform(2, s_max=6.0)]
    values = breathing_fractions(6.0, 0.2)
    plain = play(design, [values], OPTIONS)
    held = play(design, [np.repeat(values, 2)], OPTIONS)
    assert plain.ok.all() and held.ok.all()
    np.testing.assert_allclose(held.front, plain.front, atol=1e-9)
    assert held.work[0] == pytest.approx(plain.work[0], rel=1e-9)
    assert held.dissipation[0] == pytest.approx(plain.dissipation[0], rel=1e-9)


def test_the_run_converges_as_the_steps_of_s_shrink():
    """The sliding tips are carried on their cones' edges from step to step, so the work
    does not carry an error proportional to the step: halving a 0.2 mm step moves it by
    under 2 %, halving again by less than that, and the advance by under 0.01 mm."""
    design = [BristledDesign.uniform(2, s_max=10.0)]
    r = [run(design, cycles=1, options=RunOptions(ds=ds)) for ds in (0.2, 0.1, 0.05)]
    assert all(x.ok.all() for x in r)
    w = [float(x.work[0]) for x in r]
    assert abs(w[1] - w[0]) < 0.02 * w[2]
    assert abs(w[2] - w[1]) < abs(w[1] - w[0])
    adv = [float(x.net_advance[0]) for x in r]
    assert max(adv) - min(adv) < 0.01
    assert r[2].work[0] == pytest.approx(r[2].force_work[0], rel=2e-3)


def test_the_bristled_models_bristle_defaults_are_the_fe_crawlers():
    """The reduced layer cannot import the crawler's declarations: the two default
    bristles are kept equal here."""
    import dataclasses

    from bristlecrawler.crawler.spec import Bristle
    from bristlecrawler.reduced.bristled import TaperedBristle

    declared = {f.name: f.default for f in dataclasses.fields(Bristle)}
    for f in dataclasses.fields(TaperedBristle):
        assert f.default == declared[f.name], f.name
