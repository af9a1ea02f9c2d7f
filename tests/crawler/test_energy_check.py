"""The step energy check and the recorded balance use the same rules: the run's balance
residual is the sum of the errors of its steps (so bounding those bounds the residual)."""

import itertools

import jax.numpy as jnp
import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from bristlecrawler.crawler.history import CrawlerHistory
from bristlecrawler.crawler.record import EnergyCheck, energy_series

finite = st.floats(-10.0, 10.0, allow_nan=False)


def _history(t, fc, s, en):
    m = len(t)
    z2 = np.zeros((m, 2))
    return CrawlerHistory(
        t=t, s=s, left=z2, right=z2, connector_force=fc, connector_work=np.zeros(m),
        tip_position=np.zeros((m, 2, 2)), tip_state=np.zeros((m, 2), int),
        energies=energy_series(t, fc, s, en), frame_t=np.zeros(0),
        frame_nodes=np.zeros((0, 1, 2)), lines=np.zeros((0, 2), int),
        line_kind=np.zeros(0, int), substrate_xy=np.zeros((0, 2)),
    )  # fmt: skip


@settings(max_examples=60, deadline=None)
@given(
    m=st.integers(2, 12),
    data=st.data(),
)
def test_balance_residual_is_the_sum_of_step_errors(m, data):
    dt = data.draw(arrays(float, m - 1, elements=st.floats(1e-6, 0.1)))
    t = np.concatenate([[0.0], np.cumsum(dt)])
    fc = data.draw(arrays(float, m, elements=finite))
    s = data.draw(arrays(float, m, elements=finite))
    en = data.draw(arrays(float, (m, 6), elements=finite))
    recs = [
        {"t": jnp.asarray(t[i]), "fc": jnp.asarray(fc[i]), "stretch": jnp.asarray(s[i]),
         "energies": jnp.asarray(en[i])}
        for i in range(m)
    ]  # fmt: skip
    steps = [float(EnergyCheck.error(a, b)) for a, b in itertools.pairwise(recs)]
    res = _history(t, fc, s, en).energy_balance_residual()
    np.testing.assert_allclose(res[1:] - res[0], np.cumsum(steps), atol=1e-9)
    tol, loss = 0.37, 0.11
    err = np.asarray(steps)
    # Energy created is measured against tol, energy lost against loss_tol (default none).
    ratios = [float(EnergyCheck(tol)(a, b)) for a, b in itertools.pairwise(recs)]
    np.testing.assert_allclose(ratios, np.maximum(-err, 0.0) / tol, rtol=1e-12, atol=1e-12)
    ratios = [float(EnergyCheck(tol, loss)(a, b)) for a, b in itertools.pairwise(recs)]
    want = np.where(err < 0, -err / tol, err / loss)
    np.testing.assert_allclose(ratios, want, rtol=1e-12, atol=1e-12)


def test_a_step_that_creates_energy_is_refused():
    """Kinetic energy from nothing (no work, nothing stored or lost elsewhere)."""
    a = {"t": 0.0, "fc": 0.1, "stretch": 1.0, "energies": jnp.zeros(6)}
    b = {"t": 1e-3, "fc": 0.1, "stretch": 1.0, "energies": jnp.array([0, 2e-3, 0, 0, 0, 0.0])}
    assert float(EnergyCheck.error(a, b)) == -2e-3
    assert float(EnergyCheck(1e-3)(a, b)) > 1.0 >= float(EnergyCheck(1e-2)(a, b))
    # The same kinetic energy paid by the connector closes the balance.
    c = dict(b, stretch=1.02)
    assert abs(float(EnergyCheck.error(a, c))) < 1e-15


def test_a_step_that_loses_energy_is_refused_only_under_a_loss_bound():
    """Kinetic energy lost (an inelastic impact: no work, nothing stored or dissipated)."""
    a = {"t": 0.0, "fc": 0.1, "stretch": 1.0, "energies": jnp.array([0, 3e-3, 0, 0, 0, 0.0])}
    b = {"t": 1e-3, "fc": 0.1, "stretch": 1.0, "energies": jnp.zeros(6)}
    assert float(EnergyCheck.error(a, b)) == 3e-3
    assert float(EnergyCheck(1e-3)(a, b)) == 0.0
    assert float(EnergyCheck(1e-3, 1e-3)(a, b)) > 1.0 >= float(EnergyCheck(1e-3, 1e-2)(a, b))
    # A non-finite balance is refused whatever the bounds.
    c = dict(b, energies=jnp.array([0, jnp.nan, 0, 0, 0, 0.0]))
    assert not float(EnergyCheck(1e-3)(a, c)) <= 1.0
