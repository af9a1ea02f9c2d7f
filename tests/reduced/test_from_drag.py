"""The reduced crawler built from drag-test parameters."""

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from bristlecrawler.errors import InputError
from bristlecrawler.reduced import ReducedCrawler, Sin2Stroke, closed_form, simulate


def _summary(k, fp, fn):
    return {"k_N_per_mm": k, "fp_N": fp, "fn_N": fn, "fp_scatter_N": 0.01}


@given(
    k=st.floats(0.2, 5.0),
    fp=st.floats(0.05, 1.0),
    ratio=st.floats(1.01, 4.0),
    s_max=st.floats(5.0, 30.0),
)
def test_a_drag_tests_crawler_advances_as_the_closed_form_says(k, fp, ratio, s_max):
    """Any F_n > F_p gives the paper's closed form (the rear bristle holds on every
    extension); F_n = F_p is the symmetric case of the next test."""
    crawler = ReducedCrawler.from_drag(_summary(k, fp, ratio * fp))
    r = simulate(crawler, Sin2Stroke(s_max, 20.0), cycles=3, samples_per_cycle=400)
    expected = closed_form.net_advance(s_max, fp / k, 3)
    assert r.net_advance == pytest.approx(expected, rel=1e-9, abs=1e-9)


def test_a_bristle_that_resists_both_ways_alike_gives_no_net_advance():
    """F_n below F_p (within the scatter of a symmetric bristle) is taken as F_n = F_p:
    the gait is then mirror-symmetric and the crawler breathes on the spot."""
    crawler = ReducedCrawler.from_drag(_summary(1.0, 0.30, 0.29))
    assert crawler.fn[0] == crawler.fp[0] == 0.30
    r = simulate(crawler, Sin2Stroke(20.0, 20.0), cycles=2, samples_per_cycle=400)
    assert abs(r.net_advance) < 1e-9


def test_one_drag_test_per_bristle_places_them_and_keeps_their_values():
    tests = [_summary(1.0, 0.2, 0.5), _summary(2.0, 0.3, 0.6), _summary(3.0, 0.4, 0.7)]
    c = ReducedCrawler.from_drag(tests, segment_lengths=[30.0, 70.0])
    assert c.n_bristles == 3 and c.length == 100.0
    np.testing.assert_array_equal(c.k, [1.0, 2.0, 3.0])
    np.testing.assert_array_equal(c.fn, [0.5, 0.6, 0.7])


class _Result:
    def summary(self):
        return _summary(0.5, 0.25, 0.4)


def test_a_drag_result_is_read_through_its_summary():
    c = ReducedCrawler.from_drag(_Result(), n_bristles=4, length=60.0)
    np.testing.assert_array_equal(c.segment_lengths, [20.0, 20.0, 20.0])
    assert c.fp[3] == 0.25


@pytest.mark.parametrize(
    ("summary", "words"),
    [
        (_summary(1.0, 0.2, math.nan), "no F_n: it never slid against the grain"),
        (_summary(math.nan, 0.2, 0.3), "no k"),
        (_summary(1.0, -0.2, 0.3), "no F_p"),
        ({"k_N_per_mm": 1.0, "fp_N": 0.2}, r"no F_n \(fn_N\)"),
    ],
)
def test_a_drag_test_without_a_parameter_is_refused_with_its_name(summary, words):
    with pytest.raises(InputError, match=words):
        ReducedCrawler.from_drag(summary)
