"""A contact node on a substrate: forces/tangents by autodiff, and the pressed-and-dragged
cantilever solved with the kernel against the linearised analytic answer."""

import math

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from bristlecrawler.contact import (
    SLIP,
    STICK,
    CoulombLaw,
    Flat,
    Grooves,
    node_force,
    node_potential,
    node_step,
    project,
)
from bristlecrawler.verification.contact_refs import (
    cantilever_drag,
    inclined_cantilever_compliance,
)

LAW = CoulombLaw(mu=0.65, k_n=1e5, k_t=1e5)
force = jax.jit(node_force)
stiff = jax.jit(jax.jacfwd(node_force))
pot_grad = jax.jit(jax.grad(node_potential))
accept = jax.jit(node_step)


@pytest.mark.slow
@pytest.mark.parametrize(
    ("x", "anchor"),
    [
        ((0.3, -1e-6), 0.6),  # groove bottom, stick (arc length of the foot is 0.75)
        ((-0.5, -2e-6), -0.4),  # land, slip
        ((0.05, -0.1), 0.55),  # wall of the groove, stick
        ((0.1, -0.1), 0.61),  # wall, slip
    ],
)
def test_node_force_and_tangent_by_autodiff(x, anchor):
    sub = Grooves(width=1.0, depth=0.25, pitch=2.0)
    x = jnp.array(x)
    if x[0] > 0.01:  # move the wall points just inside the wall
        x = x.at[0].set(-1e-6 if x[0] < 0.07 else -2e-6)
    f = force(x, anchor, sub, LAW)
    _, r = accept(x, anchor, sub, LAW)
    assert float(r.p_n) > 0
    # the force is p_N n and the friction along the tangent: |f_t| <= mu p_N
    assert abs(float(r.f_t)) <= 0.65 * float(r.p_n) * (1 + 1e-12)
    assert float(jnp.linalg.norm(f)) == pytest.approx(math.hypot(r.p_n, r.f_t), rel=1e-9)
    # consistent tangent = finite differences of the exact force
    h = 1e-10
    fd = np.stack(
        [
            (force(x + h * e, anchor, sub, LAW) - force(x - h * e, anchor, sub, LAW)) / (2 * h)
            for e in jnp.eye(2)
        ],
        axis=1,
    )
    np.testing.assert_allclose(stiff(x, anchor, sub, LAW), fd, rtol=1e-5, atol=1e-3)
    # grad of the incremental potential gives the same force
    np.testing.assert_allclose(pot_grad(x, anchor, sub, LAW), f, rtol=1e-10, atol=1e-12)


@pytest.mark.slow
@pytest.mark.parametrize("corner", ["land edge", "groove foot"])
@pytest.mark.parametrize("slide", [1e-7, 0.05])
def test_tangent_on_a_fillet_arc_matches_finite_differences(corner, slide):
    """The consistent tangent where the closest primitive is a fillet arc: its curvature
    enters through the second derivatives of the projection (grad s = t / (1 - kappa g)),
    which :func:`project` takes through the winning primitive alone."""
    sub = Grooves(width=1.0, depth=0.25, pitch=2.0, fillet_top=0.05, fillet_bottom=0.08)
    # Groove 0 spans 0 <= x <= 1: the land edge at (0, 0) is convex (solid to its left),
    # the foot of the wall at (0, -0.25) concave. A point 1 micrometre inside the solid,
    # on the ray at 45 degrees from the fillet's centre through the arc's middle.
    centre, radius, convex = {
        "land edge": (jnp.array([-0.05, -0.05]), 0.05, True),
        "groove foot": (jnp.array([0.08, -0.17]), 0.08, False),
    }[corner]
    d = jnp.array([1.0, 1.0] if convex else [-1.0, -1.0]) / math.sqrt(2.0)
    x = centre + (radius - 1e-6 if convex else radius + 1e-6) * d
    pr = project(sub, x)
    assert float(pr.gap) == pytest.approx(-1e-6, abs=1e-12)
    np.testing.assert_allclose(pr.normal, d if convex else -d, atol=1e-12)  # on the arc
    anchor = float(pr.arc_length) + slide  # 1e-7 mm: stick; 0.05 mm: slip
    _, r = accept(x, anchor, sub, LAW)
    assert int(r.state) == (STICK if slide < 1e-3 else SLIP)
    h = 1e-9
    # the force is -p_N grad g + f_t grad s, with the gradients by finite differences of
    # the projection's values (on the arc, grad s = t / (1 - kappa g))
    grads = [
        np.array(
            [
                (getattr(project(sub, x + h * e), k) - getattr(project(sub, x - h * e), k))
                / (2 * h)
                for e in jnp.eye(2)
            ]
        )
        for k in ("gap", "arc_length")
    ]
    want = -float(r.p_n) * grads[0] + float(r.f_t) * grads[1]
    np.testing.assert_allclose(force(x, anchor, sub, LAW), want, rtol=1e-6, atol=1e-9)
    fd = np.stack(
        [
            (force(x + h * e, anchor, sub, LAW) - force(x - h * e, anchor, sub, LAW)) / (2 * h)
            for e in jnp.eye(2)
        ],
        axis=1,
    )
    np.testing.assert_allclose(stiff(x, anchor, sub, LAW), fd, rtol=1e-5, atol=1e-3)


@jax.jit
def _solve(x, anchor, h, k_tip, press, direction):
    """Newton for K (x - free) + contact force = 0, free = clamp offset (direction h, -press)."""
    free = jnp.stack([direction * h, -press])
    sub = Flat(0.0)

    def newton(_, x):
        r = k_tip @ (x - free) + node_force(x, anchor, sub, LAW)
        j = k_tip + jax.jacfwd(node_force)(x, anchor, sub, LAW)
        return x - jnp.linalg.solve(j, r)

    return jax.lax.fori_loop(0, 30, newton, x)


def _drag(k_tip, press, direction, h_max, n_steps):
    """Quasi-static drag of a tip on elastic springs K about the clamp (stiffness N/mm)."""
    # start just inside the plane so that the first Newton iterate sees the contact
    x, anchor = jnp.array([0.0, -1e-9]), 0.0
    states, p_n, f_t, hs = [], [], [], np.linspace(0.0, h_max, n_steps + 1)
    for h in hs:
        x = _solve(x, anchor, h, jnp.asarray(k_tip), press, float(direction))
        anchor, r = accept(x, anchor, Flat(0.0), LAW)
        states.append(int(r.state))
        p_n.append(float(r.p_n))
        f_t.append(float(r.f_t))
    return hs, np.array(states), np.array(p_n), np.array(f_t)


@pytest.mark.parametrize(("alpha", "direction"), [(0.0, 1), (math.pi / 8, -1)])
def test_pressed_cantilever_sticks_then_slips_as_the_linearised_answer(alpha, direction):
    c = inclined_cantilever_compliance(5.0, 10.0, 100.0, alpha)
    ref = cantilever_drag(c, 0.01, 0.65, direction)
    assert not ref.self_locks and not ref.slips_on_press
    hs, states, p_n, f_t = _drag(np.linalg.inv(c), 0.01, direction, 2 * ref.drag_at_slip, 200)
    first = int(np.argmax(states == SLIP))
    assert np.all(states[:first] == STICK)
    dh = hs[1] - hs[0]
    # slip starts within one load step (plus the penalty compliance) of h*
    assert hs[first - 1] <= ref.drag_at_slip * (1 + 1e-3) and hs[first] >= ref.drag_at_slip
    assert hs[first] - ref.drag_at_slip <= dh * 1.001
    assert p_n[0] == pytest.approx(ref.normal_at_press, rel=2e-3)
    assert p_n[-1] == pytest.approx(ref.normal_in_slip, rel=2e-3)
    assert abs(f_t[-1]) == pytest.approx(ref.friction_in_slip, rel=2e-3)


def test_pressed_cantilever_wedges_where_the_reference_says_it_self_locks():
    c = inclined_cantilever_compliance(5.0, 10.0, 100.0, math.pi / 8)
    assert cantilever_drag(c, 0.01, 0.65, 1).self_locks
    _, states, p_n, _ = _drag(np.linalg.inv(c), 0.01, 1, 0.5, 25)
    assert np.all(states == STICK)
    assert np.all(np.diff(p_n) > 0)  # dragging only presses the tip harder
