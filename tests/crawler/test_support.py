"""A bristle must carry its share of the weight on its tip: designs where it would lie on
its face are refused before any work, with the reason."""

import dataclasses
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from bristlecrawler.crawler.model import build
from bristlecrawler.crawler.spec import Bristle, Contact, CrawlerSpec
from bristlecrawler.crawler.support import support
from bristlecrawler.errors import InputError
from bristlecrawler.verification.contact_beam_cases import bristle_compliance


def _level_face_deg(b: Bristle) -> float:
    """Inclination at which the tapered bristle's lower face is level."""
    return math.degrees(math.atan(2.0 * b.length / (b.thickness_clamp - b.thickness_tip)))


@pytest.mark.slow
@pytest.mark.parametrize("alpha", [20.0, 45.0, 70.0])
def test_the_clearance_is_the_built_crawlers_clamp_corner_over_its_tip(alpha):
    spec = CrawlerSpec.paper().replace_bristles(alpha_deg=alpha)
    cm = build(spec)
    b = spec.bristles[0]
    X = np.asarray(cm.model.params.X)[:, :2]
    chain = cm.bristles[0]
    n = b.normal()
    th = b.node_thickness()
    pairs = zip(chain, th, strict=True)
    lowest = [min(X[k, 1] + s * 0.5 * h * n[1] for s in (-1, 1)) for k, h in pairs]
    assert lowest[0] - lowest[-1] == pytest.approx(support(b, 0.0).clearance_mm, abs=1e-9)


@pytest.mark.parametrize("alpha", [10.0, 45.0, 70.0])
def test_the_least_sag_is_the_held_tips_vertical_compliance(alpha):
    """A held tip: the vertical force over the vertical displacement with the horizontal
    one zero, 1 / (C^-1)_yy of the closed-form tip compliance (no shear)."""
    b = Bristle(alpha_deg=alpha, shear=False)
    C = bristle_compliance(math.radians(alpha))
    held = 1.0 / np.linalg.inv(C)[1, 1]
    assert support(b, 1.0).sag_mm == pytest.approx(held, rel=1e-9)


def test_the_paper_crawler_and_its_inclinations_up_to_70_degrees_are_accepted():
    for alpha in (0.0, 30.0, 45.0, 60.0, 70.0):
        CrawlerSpec.paper().replace_bristles(alpha_deg=alpha).check()


def test_a_bristle_beyond_its_level_face_is_refused_even_without_weight():
    """Without gravity (the contact penalty sized by a given load instead)."""
    b = Bristle()
    weightless = CrawlerSpec.paper(gravity=0.0, contact=Contact(penalty_load=0.1))
    spec = weightless.replace_bristles(alpha_deg=_level_face_deg(b) + 0.5)
    with pytest.raises(InputError, match="bristles\\[0\\] cannot carry the body"):
        spec.check()
    weightless.replace_bristles(alpha_deg=_level_face_deg(b) - 0.5).check()


def test_no_weight_and_no_penalty_load_is_refused():
    """Nothing would press the bristles down or size the contact penalty: the spec says so
    in one line, as a scenario file does."""
    with pytest.raises(InputError, match="gravity = 0 leaves no weight") as err:
        CrawlerSpec.paper(gravity=0.0).check()
    assert "\n" not in str(err.value)


@settings(max_examples=40, deadline=None)
@given(
    alpha=st.floats(0.0, 79.0),
    e=st.floats(0.3, 5.0),
    factor=st.floats(1.0, 10.0),
)
def test_stiffer_bristles_and_lighter_bodies_carry_whatever_a_design_carries(alpha, e, factor):
    """Refusal is monotone: a stiffer bristle or a lighter body carries at least every
    design the other carries."""

    def carries(spec):
        try:
            spec.check()
            return True
        except InputError as exc:
            assert "cannot carry the body" in str(exc)
            return False

    base = CrawlerSpec.paper().replace_bristles(alpha_deg=alpha, youngs_modulus=e)
    if carries(base):
        assert carries(base.replace_bristles(youngs_modulus=e * factor))
        body = dataclasses.replace(base.body, mass=base.body.mass / factor)
        assert carries(dataclasses.replace(base, body=body))


def test_the_cli_refuses_a_lying_bristle_with_one_line_and_code_2(run_cli, tmp_path):
    out = tmp_path / "run"
    code, _, err = run_cli(
        ["simulate", "paper", "--set", "bristle.alpha_deg=75", "--out", str(out)]
    )
    assert code == 2
    lines = [line for line in err.splitlines() if line.strip()]
    assert len(lines) == 1 and "cannot carry the body" in lines[0]
    assert not out.exists()
