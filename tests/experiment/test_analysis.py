"""End to end: synthetic recordings made by the models are analysed back (issue #6)."""

import numpy as np
import pytest

from bristlecrawler.errors import InputError
from bristlecrawler.experiment import (
    Recording,
    SensorModel,
    analyze,
    read_recording,
    synthetic_recording,
    write_csv,
    write_tdms,
)
from bristlecrawler.reduced import ReducedCrawler


@pytest.mark.parametrize(
    ("actuator", "c", "fmt", "skip"),
    [
        ("sma", 0.95, ".csv", 0.0),
        ("sin2", 0.95, ".tdms", 7.0),
        ("sin2", 0.6, ".csv", 0.0),
        ("sma", 1.5, ".tdms", 7.0),
    ],
)
def test_fit_recovers_generating_fp_over_k(actuator, c, fmt, skip, tmp_path):
    k = 0.48
    crawler = ReducedCrawler.two_bristle(k=k, fp=c * k)
    rec = synthetic_recording(crawler, actuator=actuator, sensor=SensorModel(skip_s=skip), seed=1)
    path = tmp_path / f"rec{fmt}"
    (write_csv if fmt == ".csv" else write_tdms)(rec, path)
    a = analyze(read_recording(path))
    assert a.signals.n_cycles == (5 if skip == 0 else 4)
    assert a.fit.first_cycle_unloaded == (skip == 0)
    assert a.fit.fp_over_k_mm == pytest.approx(c, rel=0.02)
    lo, hi = a.fit.fp_over_k_ci_mm
    assert lo <= a.fit.fp_over_k_mm <= hi and hi - lo < 0.05 * c
    assert a.fit.fp_over_k_from_advance_mm == pytest.approx(c, rel=0.05)
    # F_p and k from the recorded connector force.
    assert a.fit.fp_N == pytest.approx(c * k, rel=0.02)
    assert a.fit.k_N_per_mm == pytest.approx(k, rel=0.03)
    # Steady cycles advance by about s~ - 4 F_p/k (paper eq. 4.15).
    steady = a.advance_per_cycle[1:] if skip == 0 else a.advance_per_cycle
    np.testing.assert_allclose(steady, a.fit.s_max_mm[-steady.size :] - 4 * c, atol=0.1)


def test_transitions_sit_where_theory_puts_them():
    c = 0.95
    rec = synthetic_recording(actuator="sin2", seed=2)
    a = analyze(rec)
    first = [tr for tr in a.transitions if tr.cycle == 1]
    later = [tr for tr in a.transitions if tr.cycle > 1]
    contraction_1 = next(tr for tr in first if tr.branch == "contraction")
    assert contraction_1.s == pytest.approx(2 * c, abs=0.1)
    assert contraction_1.slope_before == pytest.approx(-0.5, abs=0.02)
    assert contraction_1.slope_after == pytest.approx(0.0, abs=0.02)
    for tr in later:
        if tr.branch == "contraction":
            assert tr.s == pytest.approx(4 * c, abs=0.1)
        else:  # re-extension: both stick (slope -1/2) then the right tip slides (slope -1)
            assert tr.s == pytest.approx(20.0 - 4 * c, abs=0.1)
            assert tr.slope_before == pytest.approx(-0.5, abs=0.02)
            assert tr.slope_after == pytest.approx(-1.0, abs=0.02)
    assert len(a.transitions) == 2 * a.signals.n_cycles


def test_work_gives_fp_and_k():
    rec = synthetic_recording(actuator="sin2", seed=3)
    rec = Recording(rec.t, rec.left, rec.right, source="no force")
    from bristlecrawler.reduced import closed_form

    w = float(closed_form.work(20.0, 0.456, 0.48, 5))
    a = analyze(rec, work_mJ=w)
    assert a.fit.fp_N == pytest.approx(0.456, rel=0.02)
    assert a.fit.k_N_per_mm == pytest.approx(0.48, rel=0.03)


def test_long_dropout_is_refused_with_its_time():
    rec = synthetic_recording(actuator="sin2", sensor=SensorModel(dropouts=0), seed=4)
    left = rec.left.copy()
    left[3000:3200] = np.nan
    bad = Recording(rec.t, left, rec.right, source="gappy")
    with pytest.raises(InputError, match=r"dropout of 2.01 s at t=30 s"):
        analyze(bad)


def test_recordings_without_a_complete_cycle_are_refused():
    t = np.arange(500) / 100.0
    with pytest.raises(InputError, match="no strokes"):
        analyze(Recording(t, 0.1 * t, 0.1 * t, source="both ends move together"))
    # A single contraction that never re-extends is not a cycle.
    s = np.minimum(t, 2.0) * 5
    with pytest.raises(InputError, match="no complete stroke cycle"):
        analyze(Recording(t, s, np.zeros_like(t), source="half a cycle"))
