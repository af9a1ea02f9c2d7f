"""Contact as a term of the FE dynamic solver: the Coulomb oscillator (issue #4 case)."""

import numpy as np
import pytest

from bristlecrawler.verification.contact_cases import coulomb_oscillator_fe


@pytest.fixture(scope="module")
def run():
    return coulomb_oscillator_fe()


def test_turning_points_and_stop_time(run):
    ref = run.reference
    assert run.turning_points.size == ref.positions.size
    np.testing.assert_allclose(run.turning_points, ref.positions, atol=0.01)
    assert run.stop_time == pytest.approx(ref.stop_time, abs=2e-3)  # dt = 1 ms


def test_friction_dissipation_accounts_for_the_lost_energy(run):
    # Dissipation accumulated by the return mapping vs the spring energy lost: independent.
    assert run.energy_balance_rel_error < 1e-4
