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
from bristlecrawler.verification.cases import N_ELEM, cantilever

# Same mesh and scheme as the verification's energy case: the compiled programs are shared.
SCHEME = Integrator.newmark(0.25, 0.5, rtol=1e-12)


@pytest.fixture(scope="module")
def model():
    m = cantilever(N_ELEM)
    return m.with_params(load_vec=jnp.asarray([[0.0, 0.0, 0.0]]))


def _released(m, scale=1e-3):
    """State released from rest after a static tip-load preload (in the model's units)."""
    EI = float(m.params.sec[0, 0] * m.params.sec[0, 2] * m.params.sec[0, 3] ** 3 / 12.0)
    pre = m.with_params(load_vec=jnp.asarray([[0.0, scale * EI, 0.0]]))
    return initial_state(m, q=solve_static(pre).state.q)


def test_vmap_step_matches_individual_runs(model):
    step = make_step(model.topology, model.terms, SCHEME)
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
    EI, rhoA = 1e-6 / 12, 1e-2  # cantilever(): E = 1 MPa, b = 1 mm, h = 0.01 mm, rho = 1
    T1 = 2 * np.pi / (1.8751**2 * np.sqrt(EI / rhoA))
    dt = T1 / 20
    ig = SCHEME
    E0 = energy(s0, model)["total"]
    free, _ = run_fixed(model, s0, model.params, dt, 100, ig)
    damped_model = Rayleigh.from_ratio(0.05, 2 * np.pi / T1).apply(model)
    damped, _ = run_fixed(damped_model, s0, damped_model.params, dt, 100, ig)
    assert abs(energy(free, model)["total"] - E0) < 1e-6 * E0
    # Mass-proportional damping, 5 % of critical: energy ~ exp(-2 zeta w t) = e^-3.1 after
    # 5 periods (bound e^-2.5 leaves room for the higher modes' smaller modal damping).
    assert energy(damped, model)["total"] < np.exp(-2.5) * E0


def test_failure_is_a_status_and_throw_raises(model):
    step = make_step(model.topology, model.terms, SCHEME)
    s0 = _released(model)
    bad = model.with_params(sec=model.params.sec.at[3, 0].set(jnp.nan))  # E = NaN
    s1, info = step(s0, bad.params, jnp.asarray(1.0))
    assert int(info.status) != 0
    assert np.array_equal(np.asarray(s1.u), np.asarray(s0.u))  # state untouched
    text = message(info, "dynamics")
    assert "t = " in text and "NaN" in text
    big = model.with_params(load_vec=jnp.asarray([[0.0, 1.0, 0.0]]))
    opts = StaticOptions(min_increment=0.3, max_rotation=1e-3)
    res = solve_static(big, options=opts, throw=False)
    assert not res.ok and "load factor" in res.message
    with pytest.raises(SolverError, match="static solve"):
        solve_static(big, options=opts)
