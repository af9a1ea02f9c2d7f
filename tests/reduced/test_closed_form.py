"""Closed forms of the two-bristle crawler: paper values, continuity, calibration round trip."""

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from bristlecrawler.errors import InputError
from bristlecrawler.reduced import calibrate
from bristlecrawler.reduced import closed_form as cf


def test_paper_numbers():
    # Paper Section 4: s~ = 20 mm, F_p/k = 0.95 mm, 5 cycles -> about 82 mm.
    assert cf.net_advance(20.0, 0.95, 5) == pytest.approx(20 - 3 * 0.95 + 4 * (20 - 4 * 0.95))
    assert cf.net_advance(20.0, 0.95, 5) == pytest.approx(82.0, abs=0.1)
    # 75 mJ over 5 cycles with F_p = 0.45 N, k = 0.48 N/mm, as the paper reports.
    assert cf.work(20.0, 0.4547, 0.48, 5) == pytest.approx(75.0, rel=0.01)


def test_calibration_matches_paper():
    cal = calibrate(20.0, 5, 82.0, 75.0)
    assert cal.fp_over_k_mm == pytest.approx(0.947, abs=5e-4)
    assert cal.fp_N == pytest.approx(0.455, abs=5e-4)
    assert cal.k_N_per_mm == pytest.approx(0.480, abs=5e-4)
    assert calibrate(20.0, 5, 82.0).fp_N is None


@given(s=st.floats(1.0, 50.0), c=st.floats(0.01, 30.0), n=st.integers(1, 20))
def test_regime_formulas_are_continuous_in_c(s, c, n):
    eps = 1e-9 * s
    for edge in (s / 4, s / 2):
        lo, hi = cf.net_advance(s, edge - eps, n), cf.net_advance(s, edge + eps, n)
        assert abs(lo - hi) < 1e-6 * s * n
        wl, wh = cf.work(s, edge - eps, 1.0, n), cf.work(s, edge + eps, 1.0, n)
        assert abs(wl - wh) < 1e-6 * s * s * n
    # Motion and work are never negative and the advance never exceeds n s~.
    assert 0.0 <= cf.net_advance(s, c, n) < n * s
    assert cf.work(s, c, 1.0, n) >= 0.0


@given(s=st.floats(1.0, 50.0), c=st.floats(0.01, 0.49), n=st.integers(1, 20), k=st.floats(0.01, 10))
def test_calibration_round_trip(s, c, n, k):
    c = c * s  # F_p/k below s~/2, i.e. some motion
    adv = float(cf.net_advance(s, c, n))
    w = float(cf.work(s, c * k, k, n))
    cal = calibrate(s, n, adv, w)
    assert cal.fp_over_k_mm == pytest.approx(c, rel=1e-9)
    assert cal.k_N_per_mm == pytest.approx(k, rel=1e-8)
    assert cal.regime == cf.regime(s, c)


@pytest.mark.parametrize(
    ("adv", "work", "word"),
    [
        (120.0, None, "smaller than"),
        (0.0, None, "not positive"),
        (-1.0, None, "not positive"),
        (82.0, -3.0, "work"),
        (np.inf, None, "finite"),
    ],
)
def test_impossible_calibrations_are_refused(adv, work, word):
    with pytest.raises(InputError, match=word):
        calibrate(20.0, 5, adv, work)


def test_vectorised_over_a_million_designs():
    rng = np.random.default_rng(0)
    s = rng.uniform(1, 40, 1_000_000)
    c = rng.uniform(0.01, 25, 1_000_000)
    k = rng.uniform(0.1, 2, 1_000_000)
    adv = cf.net_advance(s, c, 5)
    work = cf.work(s, c * k, k, 5)
    assert adv.shape == work.shape == (1_000_000,)
    idx = rng.integers(0, s.size, 50)
    for i in idx:  # element-wise agreement with scalar evaluation
        assert adv[i] == cf.net_advance(float(s[i]), float(c[i]), 5)
        assert work[i] == cf.work(float(s[i]), float(c[i] * k[i]), float(k[i]), 5)
    # All three regimes are represented and each is where theory puts it.
    reg = cf.regime(s, c)
    assert set(np.unique(reg)) == {1, 2, 3}
    assert np.all(adv[reg == 1] == 0.0)


def test_work_equals_dissipation_in_steady_cycles():
    s, c, k = 20.0, 0.95, 0.48
    traj_end = cf.trajectory(
        np.array([0.0, 0.0]), np.array([2, 3]), np.array([False, False]), s, c * k, k
    )
    # Between the ends of cycles 2 and 3 the elastic energy is unchanged: work = dissipation.
    dW = np.diff(traj_end.work)[0]
    assert dW == pytest.approx(cf.work_later(s, c * k, k))
    assert np.diff(traj_end.elastic_energy)[0] == pytest.approx(0.0, abs=1e-12)
