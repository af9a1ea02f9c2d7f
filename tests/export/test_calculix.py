"""CalculiX on the exported decks (where ``ccx`` is installed; CI installs it)."""

from __future__ import annotations

import dataclasses
import shutil

import pytest

from bristlecrawler.contact.substrates import Flat
from bristlecrawler.crawler.drag import DragTest
from bristlecrawler.crawler.spec import Bristle, CrawlerSpec
from bristlecrawler.export import ContinuumOptions, continuum_deck
from bristlecrawler.export.ccx import run_ccx
from bristlecrawler.export.compare import flat_sliding, stick_stiffness
from bristlecrawler.jobs.crosscheck import (
    beam_tip_compliance,
    calculix_tip_compliance,
    series_from_calculix,
)

CCX = shutil.which("ccx")
pytestmark = pytest.mark.skipif(CCX is None, reason="CalculiX (ccx) is not installed")


@pytest.mark.slow
def test_the_continuum_bristle_bends_as_the_toolkits_beam(tmp_path):
    """Clamped, a horizontal force at the tip: the plane-stress continuum's tip compliance
    is the tapered Timoshenko beam's within 5 %, and plane strain's is plane stress's
    times 1 - nu^2 (bending and stretching; the shear part, a few per cent, keeps G)."""
    b = Bristle()
    beam = beam_tip_compliance(b)
    stress = calculix_tip_compliance(tmp_path, b, "stress", CCX)
    strain = calculix_tip_compliance(tmp_path, b, "strain", CCX)
    assert stress == pytest.approx(beam, rel=0.05)
    assert strain / stress == pytest.approx(1 - b.poisson_ratio**2, rel=0.01)


@pytest.mark.slow
def test_calculix_drags_the_bristle_at_mu_times_the_load_on_a_flat(tmp_path):
    spec = dataclasses.replace(CrawlerSpec.paper(), substrate=Flat())
    text, info = continuum_deck(
        spec, DragTest(direction="along", distance=1.0), ContinuumOptions(along=10, across=2)
    )
    (tmp_path / "drag.inp").write_text(text)
    run = run_ccx(tmp_path, "drag", exe=CCX)
    assert run.complete, run.stopped
    s = series_from_calculix(run.printed, info)
    mu = spec.contact.mu
    # The substrate carries the carriage's load and the bristle's own weight.
    assert s.normal == pytest.approx(info.load + info.bristle_weight, rel=1e-3)
    sliding, samples = flat_sliding(s, mu)
    assert samples >= 5
    assert sliding == pytest.approx(mu * s.normal, rel=0.02)
    # Before it slides the tip sticks: the force climbs from its start towards mu N.
    assert s.force[0] < 0.5 * mu * s.normal
    assert stick_stiffness(s, mu * s.normal) > 0
