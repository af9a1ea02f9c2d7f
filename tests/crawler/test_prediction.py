"""The reduced twin of an FE design: same places, same gait, drag-test bristles."""

import dataclasses
from types import SimpleNamespace

import numpy as np
import pytest

from bristlecrawler.crawler import Actuation, CrawlerSpec
from bristlecrawler.crawler.prediction import compare, reduced_gait, reduced_run, reduced_twin
from bristlecrawler.reduced import PAPER_FP, PAPER_K, closed_form

PAPER_DRAG = {"k_N_per_mm": PAPER_K, "fp_N": PAPER_FP, "fn_N": 3 * PAPER_FP}


def test_the_paper_design_with_the_papers_bristles_is_the_papers_reduced_crawler():
    spec = CrawlerSpec.paper()
    r = reduced_run(spec, PAPER_DRAG, samples_per_cycle=400)
    assert r.net_advance == pytest.approx(closed_form.net_advance(20.0, 0.95, 5), rel=1e-9)
    assert r.net_advance == pytest.approx(81.95, abs=1e-6)


def test_the_twin_has_the_designs_bristle_places():
    spec = CrawlerSpec.paper().with_bristles(4)
    twin = reduced_twin(spec, PAPER_DRAG)
    x = [b.position for b in spec.bristles]
    np.testing.assert_allclose(twin.segment_lengths, np.diff(x))
    assert twin.n_bristles == 4


def test_a_peristaltic_design_gives_the_twin_the_same_lag():
    act = Actuation(s_max=10.0, period=20.0, cycles=1, gait="peristaltic", lag=5.0)
    spec = dataclasses.replace(CrawlerSpec.paper().with_bristles(3), actuation=act)
    gait = reduced_gait(spec)
    t = np.array([5.0, 10.0, 15.0])
    s = gait.shortenings(t, cycles=1)
    np.testing.assert_allclose(s[1:, 1], s[:-1, 0], atol=1e-12)  # segment 1 is 5 s late
    assert s[1, 0] == pytest.approx(10.0)


def test_compare_sets_the_fe_history_beside_the_reduced_run():
    spec = dataclasses.replace(CrawlerSpec.paper(), actuation=Actuation(cycles=2))
    fe = SimpleNamespace(
        net_advance=30.0,
        connector_work=np.array([0.0, 20.0]),
        advance_per_cycle=lambda: np.array([16.0, 14.0]),
    )
    p = compare(spec, PAPER_DRAG, fe)
    red = reduced_run(spec, PAPER_DRAG)
    assert p.reduced_advance == pytest.approx(red.net_advance)
    assert p.advance_error == pytest.approx(red.net_advance - 30.0)
    assert p.work_error == pytest.approx(red.work[-1] / 20.0 - 1.0)
    assert p.pitch == 2.0 and p.fp_over_k == pytest.approx(0.95)
    assert p.row()["four_fp_over_k_mm"] == pytest.approx(3.8)
