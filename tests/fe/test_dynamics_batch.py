"""One compiled step, vmapped over a batch of designs; failures come back as statuses."""

import dataclasses

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from bristlecrawler.errors import SolverError
from bristlecrawler.fe import (
    Integrator,
    Rayleigh,
    SaveAt,
    StaticOptions,
    Stepper,
    energy,
    initial_state,
    make_step,
    message,
    solve,
    solve_static,
)
from bristlecrawler.verification.cases import N_ELEM, cantilever

# Same mesh and scheme as the verification's energy case: the compiled programs are shared
# (its static solver, and its 100-step ``Stepper.fixed`` scan: keep CHUNK and pass dt as a
# Python float, since a numpy/strong-typed dt is another signature and another compile).
SCHEME = Integrator.newmark(0.25, 0.5, tolerance=1e-12)
CHUNK = 100
# First bending frequency (rad/s) of cantilever(): E = 1 MPa, b = 1 mm, h = 0.01 mm, rho = 1.
W1 = 1.8751**2 * np.sqrt((1e-6 / 12) / 1e-2)  # sqrt(EI / rho A)


@pytest.fixture(scope="module")
def model():
    m = cantilever(N_ELEM)
    return m.with_params(load_vec=jnp.asarray([[0.0, 0.0, 0.0]]))


def _released(m, scale=1e-3):
    """State released from rest after a static tip-load preload (in the model's units)."""
    EI = float(m.params.sec[0, 0] * m.params.sec[0, 2] * m.params.sec[0, 3] ** 3 / 12.0)
    pre = m.with_params(load_vec=jnp.asarray([[0.0, scale * EI, 0.0]]))
    # Clamped mesh: the support check (a tangent compile) is not needed.
    return initial_state(m, q=solve_static(pre, check_support=False).state.q)


@pytest.mark.slow
def test_vmap_step_matches_individual_runs(model):
    """The jitted step vmapped over three designs (Young's moduli) takes the same CHUNK
    steps as each design run alone (the compiled ``Stepper.fixed`` scan of that step)."""
    step = make_step(model.topology, model.terms, SCHEME)
    Es = np.array([0.8, 1.0, 1.3])
    designs = [model.with_params(sec=model.params.sec.at[:, 0].set(E)) for E in Es]
    states = [_released(d) for d in designs]
    dt = 5.0
    singles = []
    for d, s in zip(designs, states, strict=True):
        s, infos = Stepper.of(d, integrator=SCHEME).fixed(s, d.params, dt, CHUNK)
        assert np.all(np.asarray(infos.status) == 0)
        singles.append(np.asarray(s.u))
    stack = jax.tree.map(lambda *x: jnp.stack(x), *[d.params for d in designs])
    sstack = jax.tree.map(lambda *x: jnp.stack(x), *states)
    batched = jax.jit(jax.vmap(step, in_axes=(0, 0, None)))
    for _ in range(CHUNK):
        sstack, info = batched(sstack, stack, jnp.asarray(dt))
        assert np.all(np.asarray(info.status) == 0)
    assert not np.allclose(singles[0], singles[2], rtol=1e-3)  # the designs differ
    assert np.allclose(np.asarray(sstack.u), np.stack(singles), rtol=1e-10, atol=1e-14)


@pytest.mark.slow
def test_mass_damping_dissipates_and_undamped_conserves(model):
    s0 = _released(model)
    T1 = 2 * np.pi / W1
    dt = float(T1 / 20)
    ig = SCHEME
    E0 = energy(s0, model)["total"]
    free, _ = Stepper.of(model, integrator=ig).fixed(s0, model.params, dt, CHUNK)
    damped_model = Rayleigh.from_ratio(0.05, 2 * np.pi / T1).apply(model)
    damped, _ = Stepper.of(damped_model, integrator=ig).fixed(s0, damped_model.params, dt, CHUNK)
    assert abs(energy(free, model)["total"] - E0) < 1e-6 * E0
    # Mass-proportional damping, 5 % of critical: energy ~ exp(-2 zeta w t) = e^-3.1 after
    # 5 periods (bound e^-2.5 leaves room for the higher modes' smaller modal damping).
    assert energy(damped, model)["total"] < np.exp(-2.5) * E0


@pytest.mark.slow
def test_stiffness_damping_takes_its_modal_ratio(model):
    """Stiffness-proportional Rayleigh damping (a1 = 2 zeta / w1, a0 = 0), the branch of
    :func:`assembly.internal_and_damping_force` that takes the K v product: the first
    mode, most of the released cantilever's energy, decays as exp(-2 zeta w1 t); the
    higher modes, damped more (zeta ~ w), take the rest. A damping force that dropped
    K v (or took it with a1 = 0) would conserve the energy and fail the upper bound."""
    s0 = _released(model)
    w1 = W1
    T1 = 2 * np.pi / w1
    dt = float(T1 / 20)
    damped_model = Rayleigh.from_ratio(0.05, w1, kind="stiffness").apply(model)
    damped, infos = Stepper.of(damped_model, integrator=SCHEME).fixed(
        s0, damped_model.params, dt, CHUNK
    )
    assert np.all(np.asarray(infos.status) == 0)
    E0 = energy(s0, model)["total"]
    ratio = energy(damped, model)["total"] / E0
    # Five periods at zeta = 0.05: exp(-2 zeta w1 t) = exp(-pi) = 0.043.
    assert np.exp(-3.5) < ratio < np.exp(-2.8)


@pytest.mark.slow
def test_mass_damping_only_topology_same_steps_and_refuses_a1(model):
    """A topology built without stiffness damping (``Structure.stiffness_damping(False)``,
    the crawler's: its programs leave the K v product out) takes the steps of the full
    program under mass-proportional damping, refuses a1 != 0 where it is set, and a step
    that meets a1 != 0 anyway fails with a fatal status: the driver stops at the first
    attempt instead of cutting dt down to dt_min."""
    from bristlecrawler.errors import InputError
    from bristlecrawler.fe.status import UNSUPPORTED_DAMPING

    w1 = W1
    dt = float(2 * np.pi / w1 / 20)
    full = Rayleigh.from_ratio(0.05, w1, kind="mass").apply(model)
    lean_topo = dataclasses.replace(model.topology, stiffness_damping=False)
    lean = dataclasses.replace(full, topology=lean_topo)
    s0 = _released(model)
    ref, _ = Stepper.of(full, integrator=SCHEME).fixed(s0, full.params, dt, CHUNK)
    got, infos = Stepper.of(lean, integrator=SCHEME).fixed(s0, lean.params, dt, CHUNK)
    assert np.all(np.asarray(infos.status) == 0)
    assert energy(got, model)["total"] < 0.5 * energy(s0, model)["total"]  # damped
    assert np.allclose(np.asarray(got.u), np.asarray(ref.u), rtol=1e-10, atol=1e-14)
    with pytest.raises(InputError, match="a1"):
        lean.with_params(damping=jnp.asarray([0.0, 1e-3]))
    with pytest.raises(InputError, match="a1"):
        Rayleigh.from_ratio(0.05, w1, kind="stiffness").apply(lean)
    # Parameters that bypass the check: the step refuses them.
    sneaky = dataclasses.replace(
        lean, params=dataclasses.replace(lean.params, damping=jnp.asarray([0.0, 1e-3]))
    )
    res = solve(sneaky, s0, 10 * dt, dt, integrator=SCHEME, throw=False)
    assert not res.ok and res.rejected == 1 and res.steps == 0 and res.records is None
    assert res.status == res.cause == UNSUPPORTED_DAMPING
    assert "stiffness-proportional damping" in res.message
    for host in (False, True):  # the compiled and the host-loop driver stop at once too
        carry, rows, failed = _drive(sneaky, s0, 10 * dt, dt, SCHEME, 8, dt * 1e-4, host)
        assert failed and len(rows["t"]) == 0
        assert int(carry.rejected) == 1 and int(carry.cause) == UNSUPPORTED_DAMPING


def test_structure_refuses_a1_without_stiffness_damping():
    from bristlecrawler.errors import InputError
    from bristlecrawler.fe import Structure, TaperedRect

    s = Structure()
    nodes = s.chain((0.0, 0.0), (1.0, 0.0), 2, TaperedRect(E=1.0, b=1.0, h0=0.01, rho=1.0))
    s.fix(nodes[0])
    s.damping(0.0, 1e-3)
    s.stiffness_damping(False)
    with pytest.raises(InputError, match="stiffness_damping"):
        s.build()
    s.stiffness_damping(True)
    assert s.build().topology.stiffness_damping


@pytest.mark.slow
def test_failure_is_a_status_and_throw_raises(model):
    s0 = _released(model)
    bad = model.with_params(sec=model.params.sec.at[3, 0].set(jnp.nan))  # E = NaN
    # Through the shared compiled scan: every step fails and leaves the state untouched.
    s1, infos = Stepper.of(bad, integrator=SCHEME).fixed(s0, bad.params, 1.0, CHUNK)
    assert np.all(np.asarray(infos.status) != 0)
    assert np.array_equal(np.asarray(s1.u), np.asarray(s0.u))  # state untouched
    info = jax.tree.map(lambda x: x[0], infos)
    text = message(info, "dynamics")
    assert "t = " in text and "NaN" in text
    big = model.with_params(load_vec=jnp.asarray([[0.0, 1.0, 0.0]]))
    opts = StaticOptions(min_increment=0.3, max_rotation=1e-3)
    res = solve_static(big, options=opts, throw=False, check_support=False)
    assert not res.ok and "load factor" in res.message
    with pytest.raises(SolverError, match="static solve"):
        solve_static(big, options=opts, check_support=False)


def _observe_tip(st, params):
    return {"t": st.t, "tip": st.u[-1, :2]}


def _drive(model, state, t_end, dt, scheme, capacity, dt_min, host=False):
    """Run the compiled (or host-loop) stepper to t_end in chunks of ``capacity`` steps."""
    loop = "host" if host else "compiled"
    stepper = Stepper.of(model, integrator=scheme, save=SaveAt(_observe_tip, capacity), loop=loop)
    carry, rows, failed = stepper.start(state, dt), [], False
    while float(carry.state.t) < t_end - 1e-12 and not failed:
        carry, buf, k, failed = stepper.run(carry, model.params, t_end, dt_min, dt)
        if int(k):
            rows.append(jax.tree.map(lambda b, k=int(k): np.asarray(b[:k]), buf))
        failed = bool(failed)
    if not rows:
        return carry, {"t": np.zeros(0), "tip": np.zeros((0, 2))}, failed
    return carry, jax.tree.map(lambda *r: np.concatenate(r), *rows), failed


@pytest.mark.slow
@pytest.mark.parametrize("host", [False, True], ids=["compiled", "host-loop"])
def test_compiled_driver_takes_the_steps_of_the_python_driver(model, host):
    """Same step rules (cut on failure, grow after easy steps): same accepted times and
    states, whatever the chunking of the loop, compiled or on the host."""
    m = Rayleigh(0.5, 0.0).apply(model)
    s0 = _released(m, 5.0)  # large preload: Newton needs more iterations early on
    scheme = Integrator.hht(tolerance=1e-12, max_iterations=3)
    ref = solve(m, s0, 40.0, 4.0, integrator=scheme, save=SaveAt(_observe_tip))
    carry, rec, failed = _drive(m, s0, 40.0, 4.0, scheme, capacity=7, dt_min=4e-4, host=host)
    assert not failed and ref.ok
    assert ref.rejected == int(carry.rejected) and ref.rejected > 0
    np.testing.assert_allclose(rec["t"], ref.times, rtol=1e-13)
    np.testing.assert_allclose(rec["tip"], ref.records["tip"], rtol=1e-9, atol=1e-12)


@pytest.mark.slow
@pytest.mark.parametrize("host", [False, True], ids=["compiled", "host-loop"])
def test_compiled_driver_reports_a_step_it_cannot_cut(model, host):
    """A Newton that cannot converge (one iteration allowed on a nonlinear step) stops the
    driver with STEP_TOO_SMALL at the state before the step, not with a wrong answer."""
    from bristlecrawler.fe.status import STEP_TOO_SMALL

    s0 = _released(model, 5.0)
    scheme = Integrator.hht(tolerance=1e-14, max_iterations=1)
    carry, rec, failed = _drive(model, s0, 10.0, 1.0, scheme, capacity=4, dt_min=0.1, host=host)
    assert failed
    assert int(carry.info.status) == STEP_TOO_SMALL
    assert float(carry.state.t) < 10.0
    assert len(rec["t"]) == int(carry.accepted)
    assert "step cut below its minimum" in message(carry.info, "dynamics")


@dataclasses.dataclass(frozen=True)
class _TipStepCheck:
    """Error ratio of a step: how far the tip moved in it over ``tol`` (mm)."""

    tol: float

    def __call__(self, prev, new):
        return jnp.linalg.norm(new["tip"] - prev["tip"]) / self.tol


@pytest.mark.slow
@pytest.mark.parametrize("host", [False, True], ids=["compiled", "host-loop"])
def test_driver_check_bounds_every_accepted_step(model, host):
    """A step the check refuses is cut (status STEP_ERROR) and retried: every accepted step
    satisfies the bound, the steps are smaller than without the check, and the compiled
    and host loops take the same steps."""
    from bristlecrawler.fe import StepControl
    from bristlecrawler.fe.status import STEP_ERROR

    m = model
    s0 = _released(m, 5.0)  # tip deflection 0.81 mm, first period about 600 s
    scheme = Integrator.hht(tolerance=1e-12)
    tol = 0.2 * float(jnp.linalg.norm(s0.u[-1, :2]))
    runs = {}
    for use_host in (host, not host):
        save, check = SaveAt(_observe_tip, 64), _TipStepCheck(tol)
        loop = "host" if use_host else "compiled"
        stepper = Stepper.of(m, integrator=scheme, save=save, check=check, loop=loop)
        carry, buf, k, failed = stepper.run(stepper.start(s0, 40.0), m.params, 400.0, 1e-6, 40.0)
        assert not bool(failed)
        runs[use_host] = (carry, jax.tree.map(lambda b, k=int(k): np.asarray(b[:k]), buf))
    carry, rec = runs[host]
    tips = np.concatenate([np.asarray(s0.u[-1:, :2]), rec["tip"]])
    moves = np.linalg.norm(np.diff(tips, axis=0), axis=1)
    assert np.all(moves <= tol * (1 + 1e-12))
    assert int(carry.rejected) > 0 and int(carry.cause) in (0, STEP_ERROR)
    # Without the check the same driver takes fewer, longer steps that break the bound.
    loop = "host" if host else "compiled"
    free = Stepper.of(
        m, integrator=scheme, save=SaveAt(_observe_tip, 64), control=StepControl(), loop=loop
    )
    _, b2, k2, _ = free.run(free.start(s0, 40.0), m.params, 400.0, 1e-6, 40.0)
    tips2 = np.concatenate([np.asarray(s0.u[-1:, :2]), np.asarray(b2["tip"][: int(k2)])])
    assert int(k2) < len(rec["t"])
    assert np.max(np.linalg.norm(np.diff(tips2, axis=0), axis=1)) > tol
    other_carry, other = runs[not host]
    np.testing.assert_allclose(rec["t"], other["t"], rtol=1e-12)
    assert int(carry.rejected) == int(other_carry.rejected)
