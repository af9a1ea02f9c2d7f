"""The FE crawler itself (no stand-in), on a short, coarse version of the paper's run.

Vertical bristles (alpha = 0) on a substrate placed symmetrically about the crawler's
mid-plane (lands centred under both tips and under x = L/2): the whole problem is mirror
symmetric, so the two ends must move by opposite amounts and the crawler cannot advance.
The shared coarse structure (``tests/structures.py``: 4 elements per bristle, contact at the
tips' axis points, no corner term, which its own tests cover, a 0.8 mm stroke in 0.4 s):
the same code path as
`bristlecrawler simulate` (build, gravity step, modal damping,
compiled adaptive driver, observer, history) at a fraction of the cost.
"""

import functools

import numpy as np
import pytest

from bristlecrawler.crawler import run as run_crawler
from bristlecrawler.scenario.convert import to_spec
from bristlecrawler.scenario.load import apply_overrides
from structures import MIRROR, coarse_run


@functools.cache
def _run(freeze: int):
    """The shared coarse crawler made mirror symmetric (``paper-vertical``'s values, lands
    centred under both tips); ``solver.freeze_iterations`` is part of the compiled step,
    so a frozen start is a structure of its own (slow lane)."""
    if freeze == 0:
        return coarse_run("paper-vertical", *MIRROR)
    sc = apply_overrides(
        coarse_run("paper-vertical", *MIRROR)[0], [f"solver.freeze_iterations={freeze}"]
    )
    return sc, run_crawler(to_spec(sc))


# Newton with and without the frozen-status start (solver.freeze_iterations).
@pytest.fixture(
    scope="module",
    params=[0, pytest.param(3, marks=pytest.mark.slow)],
    ids=["free", "frozen-start"],
)
def run(request):
    return _run(request.param)


@pytest.mark.slow
def test_a_frozen_start_converges_to_the_same_motion():
    """The frozen iterations only choose where Newton starts: every accepted step is
    converged on the Coulomb law, so the run ends in the same state (to the solver's
    tolerance: the step sizes may differ)."""
    (_, a), (_, b) = _run(0), _run(3)
    assert a.t[-1] == pytest.approx(b.t[-1], abs=1e-12)
    for x, y in ((a.left, b.left), (a.right, b.right), (a.tip_position, b.tip_position)):
        np.testing.assert_allclose(x[-1], y[-1], atol=1e-6)
    fa, fb = a.energies["friction"][-1], b.energies["friction"][-1]
    assert fa == pytest.approx(fb, rel=1e-4, abs=1e-9)


def test_mirror_symmetric_crawler_does_not_advance(run):
    sc, h = run
    d_left = h.left[:, 0] - h.left[0, 0]
    d_right = h.right[:, 0] - h.right[0, 0]
    # The imposed stroke is taken half by each end, in opposite directions.
    np.testing.assert_allclose(d_right - d_left, -h.s, atol=1e-9)
    assert np.max(np.abs(d_left + d_right)) < 1e-6 * sc.actuation.s_max
    np.testing.assert_allclose(h.left[:, 1], h.right[:, 1], atol=1e-9)
    assert abs(h.net_advance) < 1e-6
    # The actuator follows s(t) = s~ sin^2(pi t / T) at every recorded step.
    a = sc.actuation
    np.testing.assert_allclose(h.s, a.s_max * np.sin(np.pi * h.t / a.period) ** 2, atol=1e-9)


def test_forces_are_the_friction_scale_and_dissipation_never_decreases(run):
    sc, h = run
    weight = sc.body.mass * sc.gravity
    # Sliding at both tips is resisted by at most mu times the weight.
    assert np.max(np.abs(h.connector_force)) < 1.5 * sc.contact.mu * weight
    friction = h.energies["friction"]
    # Exact frictional dissipation (return mapping): never decreases.
    assert np.all(np.diff(friction) >= -1e-12) and friction[-1] >= 0.0
    assert h.stats["steps"] > 0 and h.stats["newton_iterations"] >= h.stats["steps"]
    # The step's compilation is timed apart (and is part of the wall time).
    assert 0.0 < h.stats["compile_time_s"] < h.stats["wall_time_s"]
    # So is the stroke (step 2) alone, with the part of the iterations it took: every
    # stroke step needs at least one.
    assert 0.0 < h.stats["stroke_wall_time_s"] < h.stats["wall_time_s"] - h.stats["compile_time_s"]
    assert h.stats["steps"] <= h.stats["stroke_newton_iterations"] < h.stats["newton_iterations"]
    # No step of the stroke created more energy than solver.energy_tol (nor lost more
    # than solver.energy_loss_tol).
    step_errors = np.diff(h.energy_balance_residual())
    assert np.min(step_errors) >= -sc.solver.energy_tol * (1 + 1e-9)
    assert np.max(step_errors) <= sc.solver.energy_loss_tol * (1 + 1e-9)
    assert 1.0 < h.stats["first_frequency_hz"] < 1e3


def test_the_dataset_holds_every_declared_quantity_with_its_unit(run):
    """The history that the declarations (crawler/quantities.py) make from the records
    has every declared quantity, and crawler.nc writes each with its dims and
    attributes, and nothing undeclared."""
    from bristlecrawler.crawler.quantities import QUANTITIES

    _, h = run
    ds = h.to_dataset()
    assert list(ds.variables) == [
        *(q.name for q in QUANTITIES if not q.coordinate),
        *(q.name for q in QUANTITIES if q.coordinate),
    ]
    for q in QUANTITIES:
        v = ds[q.name]
        assert v.dims == q.dims and v.attrs.get("units", "") == q.unit, q.name
        assert v.attrs.get("long_name", q.description) == q.description, q.name
    assert ds.sizes["bristle"] == 2 and ds.sizes["segment"] == 1
    np.testing.assert_array_equal(ds["connector_work"], ds["energy_external"])
    assert h.quantities == {}  # every declared series has an attribute of its own


def test_runs_of_one_structure_share_the_observer_and_use_their_own_laws():
    """The observer is built once per model structure, so a second run in the same
    process does not trace it again; the contact law it reports penalty energies with is
    the run's own (read from the parameters, not frozen into the first run's program)."""
    import dataclasses

    import jax.numpy as jnp

    from bristlecrawler import fe
    from bristlecrawler.crawler import build
    from bristlecrawler.crawler.record import observer

    sc, _ = _run(0)
    cms = [build(to_spec(sc)), build(to_spec(apply_overrides(sc, ["contact.stick_drift=3e-3"])))]
    assert observer(cms[0]) is observer(cms[1])
    state = fe.initial_state(cms[0].model)
    p_n, f_t = 0.3, 0.1  # N, on every contact point
    hist = tuple(
        dataclasses.replace(h, p_n=jnp.full_like(h.p_n, p_n), f_t=jnp.full_like(h.f_t, f_t))
        for h in state.history
    )
    state = dataclasses.replace(state, history=hist)
    n = sum(h.p_n.size for h in hist)
    pens = []
    for cm in cms:
        law = cm.contact_params.law
        expect = n * (0.5 * p_n**2 / float(law.k_n) + 0.5 * f_t**2 / float(law.k_t))
        pen = float(observer(cm)(state, cm.model.params)["energies"][4])
        assert pen == pytest.approx(expect, rel=1e-12)
        pens.append(pen)
    assert pens[1] > pens[0]  # the softer stick penalty stores more energy
