"""Assembly of the FE crawler's contact terms from the scenario's [contact] table."""

import numpy as np
import pytest

from bristlecrawler.contact.corner import FaceCornerContact
from bristlecrawler.contact.term import SubstrateContact
from bristlecrawler.crawler import build
from bristlecrawler.scenario.convert import to_spec
from bristlecrawler.scenario.load import load_scenario
from bristlecrawler.scenario.schema import Scenario


def build_crawler(sc):
    return build(to_spec(sc))


def _scenario(**contact):
    d = load_scenario("paper").model_dump()
    d["bristle"]["elements"] = 6
    d["contact"].update(contact)
    return Scenario.model_validate(d)


def test_corner_term_outlines_each_bristle():
    cm = build_crawler(_scenario(corners=True))
    kinds = [type(t) for t in cm.model.terms]
    assert kinds == [SubstrateContact, FaceCornerContact]
    term, p = cm.model.terms[1], cm.model.params.extra[1]
    n = 6 + 1
    assert len(term.faces) == 2 and all(len(f) == 2 * n + 1 for f in term.faces)
    for f, chain in zip(term.faces, cm.bristles, strict=True):
        assert f[:n] == chain and f[n : 2 * n] == chain[::-1] and f[-1] == chain[0]
    # the outline is as thick as the bristle: 3 mm at the clamp, 0.5 mm at the tip
    off = np.asarray(p.offset)
    np.testing.assert_allclose(np.linalg.norm(off[:, 0], axis=1), 1.5)
    np.testing.assert_allclose(np.linalg.norm(off[:, n - 1], axis=1), 0.25)
    # land edges of the paper's grooves (1 mm wide, pitch 2 mm): two corners per period
    assert np.asarray(p.corners).shape == (2, 2)
    assert build_crawler(_scenario(corners=False)).model.terms[1:] == ()


def test_a_flat_substrate_takes_the_scenarios_contact_without_a_corner_term():
    """A plane has no convex corners: switching a shipped scenario's substrate to flat
    builds the crawler and the drag test (no corner term), corner contact left on."""
    from bristlecrawler.crawler.drag import DragTest, build_drag
    from bristlecrawler.scenario.load import apply_overrides

    sc = apply_overrides(_scenario(corners=True), ["substrate.kind=flat"])
    assert sc.contact.corners
    assert [type(t) for t in build_crawler(sc).model.terms] == [SubstrateContact]
    drag = build_drag(to_spec(sc), DragTest(direction="along", distance=2.0))
    assert [type(t) for t in drag.model.terms] == [SubstrateContact]


@pytest.mark.parametrize("discs", [False, True])
def test_axis_points_as_discs_of_half_thickness(discs):
    cm = build_crawler(_scenario(surface=False, discs=discs))
    p = cm.contact_params
    r = np.asarray(p.radius)
    if not discs:
        assert np.all(r == 0)
        return
    np.testing.assert_allclose(r[:2], 0.25)  # the tips first, h1 / 2
    assert np.all(np.diff(r[2 : 2 + 5]) < 0)  # thinner towards the tip
    # the tip discs start touching the land top (1 micrometre in)
    X = np.asarray(cm.model.params.X)
    np.testing.assert_allclose(X[list(cm.tips), 1] - 0.25, -1e-3, atol=1e-12)


@pytest.mark.parametrize("drift", [1e-4, 1e-3, 1e-2])
def test_stick_drift_sets_the_stick_penalty(drift):
    # In stick a point at the friction limit of the penalty load (the weight on one
    # bristle) is displaced by exactly stick_drift; both contact terms share the law.
    sc = _scenario(stick_drift=drift)
    cm = build_crawler(sc)
    b, br = sc.body, sc.bristle
    mass = b.mass + 2 * br.density * br.width * br.length * 0.5 * (
        br.thickness_clamp + br.thickness_tip
    )
    limit = sc.contact.mu * mass * sc.gravity / 2
    for p in cm.model.params.extra:
        np.testing.assert_allclose(limit / float(p.law.k_t), drift, rtol=1e-12)
        np.testing.assert_allclose(mass * sc.gravity / 2 / float(p.law.k_n), 1e-3, rtol=1e-12)


def test_stick_drift_must_be_positive():
    with pytest.raises(ValueError, match="stick_drift"):
        _scenario(stick_drift=0.0)


@pytest.mark.parametrize(
    ("damping", "stiff"),
    [
        ({"kind": "mass"}, False),
        ({"kind": "stiffness"}, True),
        ({"kind": "explicit", "a0": 5.0, "a1": 0.0}, False),
        ({"kind": "explicit", "a0": 0.0, "a1": 1e-4}, True),
    ],
)
def test_damping_kind_decides_whether_the_programs_take_k_v(damping, stiff):
    """The crawler's programs carry the a1 K v product only for the damping kinds that have
    one, and the damping a run sets after the modal analysis (run.py) is accepted by the
    model it was built for; a1 on a mass-damped crawler is refused, not ignored."""
    from bristlecrawler import fe
    from bristlecrawler.errors import InputError

    d = load_scenario("paper").model_dump()
    d["bristle"]["elements"] = 6
    d["damping"].update(damping)
    sc = Scenario.model_validate(d)
    model = build_crawler(sc).model
    assert model.topology.stiffness_damping is stiff
    if sc.damping.kind == "explicit":
        final = fe.Rayleigh(sc.damping.a0, sc.damping.a1)
    else:
        final = fe.Rayleigh.from_ratio(sc.damping.ratio, 400.0, sc.damping.kind)
    final.apply(model)  # the run's own choice: accepted
    fe.Rayleigh.from_ratio(0.15, 400.0, "mass").apply(model)  # the settle's: accepted
    if not stiff:
        with pytest.raises(InputError, match="a1"):
            fe.Rayleigh.from_ratio(0.15, 400.0, "stiffness").apply(model)


@pytest.mark.parametrize(
    "kw", [{"compile_threads": 0}, {"compile_threads": 1.5}, {"driver": "gpu"}]
)
def test_run_options_refuse_bad_values(kw):
    from bristlecrawler.crawler import RunOptions
    from bristlecrawler.errors import InputError

    with pytest.raises(InputError, match=next(iter(kw))):
        RunOptions(**kw)
