"""The gravity step of a steep bristle: no step creates energy, and the tips stay on the
substrate (a wrong root of the first step curled the bristles up off it)."""

import importlib.util
from pathlib import Path

import numpy as np
import pytest

PATH = Path(__file__).resolve().parents[2] / "examples" / "gravity_step_energy.py"


def _example():
    spec = importlib.util.spec_from_file_location("gravity_step_energy", PATH)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.mark.slow
def test_a_60_degree_crawler_settles_without_energy_from_nothing():
    r = _example().created_per_step(60.0)
    # Settling under gravity only releases energy: nothing may appear beyond the bound.
    assert r["created_mJ"].max() <= 0.01
    # The tips press on the substrate as the body sinks; a tip lifting off it by more
    # than the contact's elastic range is a bristle that flapped.
    tips = r["tip_y_mm"]
    assert np.all(tips.max(axis=0) - tips[0] < 0.05)
