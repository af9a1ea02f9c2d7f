"""One compiled step, vmapped over a batch of designs; failures come back as statuses."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from bristlecrawler.errors import SolverError
from bristlecrawler.fe import (
    Integrator,
    Rayleigh,
    StaticOptions,
    energy,
    initial_state,
    make_step,
    message,
    run_fixed,
    solve_static,
)
from bristlecrawler.verification.cases import cantilever


@pytest.fixture(scope="module")
def model():
    m = cantilever(8)
    return m.with_params(load_vec=jnp.asarray([[0.0, 0.0, 0.0]]))


def _released(m, scale=1e-3):
    """State released from rest after a static tip-load preload (in the model's units)."""
    EI = float(m.params.sec[0, 0] * m.params.sec[0, 2] * m.params.sec[0, 3] ** 3 / 12.0)
    pre = m.with_params(load_vec=jnp.asarray([[0.0, scale * EI, 0.0]]))
    return initial_state(m, q=solve_static(pre).state.q)


def test_vmap_step_matches_individual_runs(model):
    step = make_step(model.topology, model.terms, Integrator.hht())
    Es = np.array([0.8, 1.0, 1.3])
    designs = [model.with_params(sec=model.params.sec.at[:, 0].set(E)) for E in Es]
    states = [_released(d) for d in designs]
    dt = jnp.asarray(5.0)
    singles = []
    for d, s in zip(designs, states, strict=True):
        for _ in range(3):
            s, info = step(s, d.params, dt)
            assert int(info.status) == 0
        singles.append(np.asarray(s.u))
    stack = jax.tree.map(lambda *x: jnp.stack(x), *[d.params for d in designs])
    sstack = jax.tree.map(lambda *x: jnp.stack(x), *states)
    batched = jax.vmap(step, in_axes=(0, 0, None))
    for _ in range(3):
        sstack, info = batched(sstack, stack, dt)
    assert np.all(np.asarray(info.status) == 0)
    assert np.allclose(np.asarray(sstack.u), np.stack(singles), rtol=1e-10, atol=1e-14)


def test_mass_damping_dissipates_and_undamped_conserves(model):
    s0 = _released(model)
    T1 = 2 * np.pi / (1.8751**2 * np.sqrt(1e-6 / 12 / 1e-2))
    dt = T1 / 20
    ig = Integrator.newmark()
    E0 = energy(s0, model)["total"]
    free, _ = run_fixed(model, s0, model.params, dt, 200, ig)
    damped_model = Rayleigh.from_ratio(0.05, 2 * np.pi / T1).apply(model)
    damped, _ = run_fixed(damped_model, s0, damped_model.params, dt, 200, ig)
    assert abs(energy(free, model)["total"] - E0) < 1e-6 * E0
    # Mass-proportional damping at 5 % of critical: energy ~ exp(-2 zeta w t), 10 periods.
    assert energy(damped, model)["total"] < 0.1 * E0


def test_failure_is_a_status_and_throw_raises(model):
    step = make_step(model.topology, model.terms, Integrator.hht(max_iter=1, rtol=1e-14))
    s0 = _released(model, scale=2.0)
    s1, info = step(s0, model.params, jnp.asarray(1e3))
    assert int(info.status) != 0
    assert np.array_equal(np.asarray(s1.u), np.asarray(s0.u))  # state untouched
    assert "t = " in message(info, "dynamics") and "iterations" in message(info, "dynamics")
    big = model.with_params(load_vec=jnp.asarray([[0.0, 1.0, 0.0]]))
    opts = StaticOptions(max_iter=1, min_increment=0.3, rtol=1e-14)
    res = solve_static(big, options=opts, throw=False)
    assert not res.ok and "load factor" in res.message
    with pytest.raises(SolverError, match="static solve"):
        solve_static(big, options=opts)
