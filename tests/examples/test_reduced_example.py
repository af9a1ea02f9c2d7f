"""The reduced-model example reproduces the paper's calibration targets."""

import importlib.util
from pathlib import Path

import numpy as np
import pytest

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def load(name):
    spec = importlib.util.spec_from_file_location(name, EXAMPLES / f"{name}.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_calibrated_crawler_reproduces_the_measurements():
    ex = load("reduced_paper_gait")
    # The calibrated model must give back the data it was calibrated on.
    assert ex.result.net_advance == pytest.approx(82.0, abs=1e-9)
    assert ex.result.work[-1] == pytest.approx(75.0, abs=1e-9)
    assert len(ex.advance_per_cycle) == 5
    # Later cycles advance less than the first by F_p/k (paper eqs. 4.13, 4.15).
    assert ex.advance_per_cycle[0] - ex.advance_per_cycle[1] == pytest.approx(
        ex.calibration.fp_over_k_mm
    )


def test_sma_example_gait_follows_the_turning_points():
    ex = load("sma_actuated_gait")
    adv, _ = ex.sma_gait.per_cycle()
    assert len(adv) == 5
    # Rate independence: each steady cycle advances by (peak - rest - 4 F_p/k).
    np.testing.assert_allclose(adv[1:], ex.predicted_steady, atol=1e-9)
    assert 15.0 < ex.response.cycle_durations[0] < 25.0
