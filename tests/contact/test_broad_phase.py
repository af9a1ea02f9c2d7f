"""The contact term's broad phase (``SubstrateContact.active``): the residual and its tangent
are those of evaluating every point, whether the broad phase holds (the points beyond the
``active`` lowest all clear the profile's top) or overflows (more points reach below it)."""

import functools
import math

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from bristlecrawler.contact import CoulombLaw, Grooves, Sawtooth, project, project_points
from bristlecrawler.contact.term import (
    ContactHistory,
    ContactParams,
    SubstrateContact,
    profile_top,
)
from bristlecrawler.errors import InputError

LAW = CoulombLaw(mu=0.65, k_n=1e4, k_t=1e4)
K = 12  # contact points, one per node
GROOVES = Grooves(width=1.0, depth=0.25, pitch=2.0, fillet_top=0.02)
SAW = Sawtooth(pitch=1.5, height=0.3, rise_fraction=0.4)


def _term_and_params(substrate, radius):
    X = jnp.stack([jnp.linspace(-3.0, 3.0, K), jnp.zeros(K)], axis=-1)
    off = jnp.stack([jnp.zeros(K), 0.1 * jnp.ones(K)], axis=-1)  # turns with the node
    return ContactParams(X, substrate, LAW, jnp.asarray(radius, float), off)


@functools.cache
def _evaluator(active):
    """Jitted (residual, tangent) of a term over the K points, params as arguments."""
    term = SubstrateContact(tuple(range(K)), active=active)

    def r(u, anchor, params):
        z = jnp.zeros_like(anchor)
        h = ContactHistory(anchor, z, z.astype(jnp.int32), z, z)
        return term.residual(u, u, 0.0, h, params)

    return jax.jit(r), jax.jit(jax.jacfwd(r))


def _both(active, u, anchor, params):
    return tuple(tuple(f(u, anchor, params) for f in _evaluator(a)) for a in (None, active))


def _place(rng, sub, radius, theta, pressed):
    """Node displacements (K, 3): the points in ``pressed`` 0..10 um into the solid (their
    rims for discs), the others clear of it at heights up to 1 mm above the top, many of
    them below the top (over a groove or a valley)."""
    top = float(profile_top(sub))
    X = np.asarray(_term_and_params(sub, radius).X)
    off = np.stack([-0.1 * np.sin(theta), 0.1 * np.cos(theta)], axis=-1)  # turned offset
    x0 = X[:, 0] + rng.uniform(-0.5, 0.5, K)
    centre = np.empty((K, 2))
    for i in range(K):
        if i in pressed:
            pr = project(sub, jnp.array([x0[i], top + 2.0]))
            q, n = np.asarray(pr.point), np.asarray(pr.normal)
            centre[i] = q + (radius[i] - rng.uniform(0.0, 0.01)) * n
        else:
            y = top + rng.uniform(-0.3, 1.0)
            while float(project(sub, jnp.array([x0[i], y])).gap) - radius[i] <= 1e-3:
                y += 0.05
            centre[i] = (x0[i], y)
    return jnp.asarray(np.concatenate([centre - X - off, theta[:, None]], axis=-1))


@pytest.mark.slow
@settings(max_examples=6, deadline=None)
@given(
    seed=st.integers(0, 2**31 - 1),
    n_pressed=st.integers(0, 5),
    active=st.sampled_from([2]),
    discs=st.booleans(),
    saw=st.booleans(),
)
def test_broad_phase_gives_the_full_residual_and_tangent(seed, n_pressed, active, discs, saw):
    rng = np.random.default_rng(seed)
    sub = SAW if saw else GROOVES
    radius = rng.uniform(0.05, 0.3, K) if discs else np.zeros(K)
    theta = rng.uniform(-0.3, 0.3, K)
    pressed = set(rng.choice(K, n_pressed, replace=False).tolist())
    u = _place(rng, sub, radius, theta, pressed)
    params = _term_and_params(sub, radius)
    anchor = jnp.asarray(rng.uniform(-4.0, 4.0, K))
    (f_full, J_full), (f_broad, J_broad) = _both(active, u, anchor, params)
    # exactly the pressed points carry a force
    carrying = set(np.flatnonzero(np.any(np.asarray(f_full[:, :2]) != 0.0, axis=1)).tolist())
    assert carrying == pressed
    # points reaching below the top of the profile (over a groove or pressed)
    reach = np.asarray(u[:, 1]) + 0.1 * np.cos(theta) - radius
    below = int(np.sum(reach < float(profile_top(sub))))
    term = SubstrateContact(tuple(range(K)), active=active)
    assert int(term.excess(u, params)) == max(below - active, 0)
    if below <= active:  # the broad phase is exact
        scale = 1.0 + float(jnp.max(jnp.abs(f_full)))
        assert float(jnp.max(jnp.abs(f_broad - f_full))) <= 1e-12 * scale
        jscale = 1.0 + float(jnp.max(jnp.abs(J_full)))
        assert float(jnp.max(jnp.abs(J_broad - J_full))) <= 1e-12 * jscale


@pytest.mark.slow
def test_a_disc_whose_centre_clears_the_top_but_whose_rim_does_not_is_kept():
    # Points 0..2 are discs of radius 0.1 with their centres 0.05 mm above the lands: they
    # touch, and points 3.. (no radius) are 0.02 mm above the lands. The broad phase must
    # rank by the rims (y - r): by centre height it would keep points 3.. and drop 0..2.
    radius = np.zeros(K)
    radius[:3] = 0.1
    x = np.linspace(-3.0, 3.0, K)
    x[:3] = (-2.9, -2.5, -2.1)  # on the land between x = -3 and -2 (grooves at [0, 1] + 2 j)
    top = float(profile_top(GROOVES))
    X = np.asarray(_term_and_params(GROOVES, radius).X)
    centre = np.stack([x, np.where(radius > 0, top + 0.05, top + 0.02)], axis=-1)
    u = jnp.asarray(np.concatenate([centre - X - [0.0, 0.1], np.zeros((K, 1))], axis=-1))
    params = _term_and_params(GROOVES, radius)
    (f_full, _), (f_broad, _) = _both(3, u, jnp.asarray(x), params)
    pressed = np.flatnonzero(np.abs(np.asarray(f_full[:, 1])) > 0)
    assert pressed.tolist() == [0, 1, 2]
    np.testing.assert_allclose(np.asarray(f_broad), np.asarray(f_full), rtol=0, atol=1e-12)


@pytest.mark.parametrize("active", [0, -1, 2.5])
def test_active_must_be_a_positive_whole_number(active):
    with pytest.raises(InputError, match="active"):
        SubstrateContact((0, 1), active=active)


@pytest.mark.slow
def test_profile_top_is_the_highest_surface_point():
    sub = SAW
    xs = jnp.linspace(-3.0, 3.0, 6001)
    surface = project_points(sub, jnp.stack([xs, jnp.full_like(xs, 5.0)], axis=-1)).point[:, 1]
    assert float(profile_top(sub)) == pytest.approx(float(jnp.max(surface)), abs=1e-6)
    assert math.isfinite(float(profile_top(GROOVES)))


def _integrator():
    from bristlecrawler import fe

    # no tangent predictor: a smaller program to compile, the same physics
    return fe.Integrator.hht(-0.1, predictor="constant")


STRIP_HHT = _integrator()


def _strip(active, press):
    """A 4-element strip (2 mm long, 0.5 mm thick) lying 0.01 mm above a flat plane, its
    left end lowered ``press`` mm in 5 ms (rotation fixed), contact points at its 5 nodes;
    returns the model and its state at rest."""
    from bristlecrawler import fe
    from bristlecrawler.contact import Flat
    from bristlecrawler.fe.motion import SmoothRamp

    s = fe.Structure()
    clamp = s.node(0.0, 0.01)
    s.prescribe(clamp, "x", SmoothRamp(0.0, 0.005, 0.001))
    s.prescribe(clamp, "y", SmoothRamp(-press, 0.005, 0.002))
    s.fix(clamp, "theta")
    nodes = s.chain(
        clamp, (2.0, 0.01), 4, fe.TaperedRect(E=1.1, b=30.0, h0=0.5, h1=0.5, rho=1.3e-9, nu=0.45)
    )
    s.damping(2000.0, 0.0)
    term = SubstrateContact(tuple(nodes), active=active)
    s.add_term(term, ())
    model = s.build()
    law = CoulombLaw.for_reference_load(0.65, load=0.1)
    p = SubstrateContact.params(np.asarray(model.params.X), term.nodes, Flat(0.0), law)
    model = model.with_params(extra=(p,))
    z = jnp.zeros((model.topology.n_nodes, 3))
    h = (term.history_at(z, p),)
    state = fe.DynState(jnp.asarray(0.0), jnp.zeros(model.topology.n_red), z, z, z, h)
    return model, state


def _pressed_strip(active, press):
    """:func:`_strip`, HHT run for 10 ms by :func:`fe.solve`."""
    from bristlecrawler import fe

    model, state = _strip(active, press)
    return fe.solve(model, state, 0.01, 5e-4, integrator=STRIP_HHT, throw=False)


@pytest.mark.slow
def test_a_run_with_the_broad_phase_is_the_run_without_it():
    # The clamp goes 0.02 mm down, 0.01 mm into the plane, and the strip next to it comes
    # down on the plane: two of the five points touch. A broad phase of two points (the
    # other three never evaluated) gives the same run.
    full, broad = _pressed_strip(None, 0.02), _pressed_strip(2, 0.02)
    assert full.ok and broad.ok
    assert int(jnp.sum(full.state.history[0].p_n > 0)) == 2
    np.testing.assert_allclose(np.asarray(broad.state.u), np.asarray(full.state.u), atol=1e-12)
    np.testing.assert_array_equal(broad.times, full.times)


@pytest.mark.slow
def test_more_points_below_the_top_than_active_is_a_fatal_error_naming_it():
    res = _pressed_strip(1, 0.02)  # the same run with room for one point: two touch
    assert not res.ok
    assert "active" in res.message
    # it stops at the first converged step with two points below the plane: no step cuts
    assert res.rejected == 1
    assert res.times.size > 0 and res.times[-1] < 0.01


@pytest.mark.slow
@pytest.mark.parametrize("driver", ["host", "compiled"])
def test_the_adaptive_drivers_stop_at_once_on_a_contact_overflow(driver):
    from bristlecrawler import fe
    from bristlecrawler.fe.status import CONTACT_OVERFLOW

    model, state = _strip(1, 0.02)
    stepper = fe.Stepper.of(model, integrator=STRIP_HHT, save=fe.SaveAt(_time, 64), loop=driver)
    carry, _, n, failed = stepper.run(stepper.start(state, 5e-4), model.params, 0.01, 5e-8, 5e-4)
    assert bool(failed)
    assert int(carry.cause) == CONTACT_OVERFLOW == int(carry.info.status)
    assert int(carry.rejected) == 1  # not cut down to dt_min
    assert 0 < int(n) and float(carry.state.t) < 0.01


def _time(state, params):
    return state.t
