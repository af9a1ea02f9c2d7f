"""Mirror symmetry of the FE crawler's forces: no handedness in beams, contact or friction.

Vertical bristles (alpha = 0) on grooves placed symmetrically about the body's mid-plane
(phase 0.5 mm: lands centred under x = 0, L/2 and L) make a problem that is unchanged by
the reflection x -> L - x. Every force the model computes must then commute with it: the
forces at a reflected state are the reflected forces (node i <-> its mirror node,
(f_x, f_y, m) -> (-f_x, f_y, -m)). States are random, with the bristles bent towards or away
from the land edges so that the point contact (faces and tips on the profile) and the
corner contact (land edges against the outlines) both carry load, in stick and in slip
(the anchors are those of another random state). A sign or orientation slip anywhere (a
segment normal, the outline's direction, the friction direction) breaks this at order
one; round-off leaves about 1e-13 of the force. (Tie rules at exact ties are not reached
by random states.)
"""

import functools

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from bristlecrawler.contact.coulomb import SLIP, STICK
from bristlecrawler.crawler import build
from bristlecrawler.fe import assembly
from bristlecrawler.scenario.convert import to_spec
from bristlecrawler.scenario.load import apply_overrides, load_scenario

FLIP = np.array([-1.0, 1.0, -1.0])  # (x, y, rotation) under x -> L - x


@functools.cache
def _crawler():
    sc = apply_overrides(
        load_scenario("paper-vertical"), ["bristle.elements=6", "substrate.phase=0.5"]
    )
    cm = build(to_spec(sc))
    X = np.asarray(cm.model.params.X)[:, :2]
    L = sc.body.length
    d = np.hypot(X[None, :, 0] - (L - X[:, None, 0]), X[None, :, 1] - X[:, None, 1])
    perm = np.argmin(d, axis=1)
    return cm, perm, float(d[np.arange(len(X)), perm].max())


def _mirror(a, perm):
    return jnp.asarray(np.asarray(a)[perm] * FLIP)


def _state(cm, rng, shift, drop, scale):
    """Random displacements; the bristles' lower parts moved by ``shift`` (mm, the left
    one to +x, the right one to -x: towards the land edges for shift > 0) and pressed
    ``drop`` (mm) down, most at the tip."""
    n = np.asarray(cm.model.params.X).shape[0]
    u = np.zeros((n, 3))
    u[:, 0] = rng.normal(0.0, scale, n)
    u[:, 1] = rng.normal(0.0, 0.2 * scale, n)
    u[:, 2] = rng.normal(0.0, 0.05 * scale, n)
    for chain, sign in zip(cm.bristles, (1.0, -1.0), strict=True):
        frac = np.linspace(0.0, 1.0, len(chain))
        u[list(chain), 0] += sign * shift * frac
        u[list(chain), 1] -= 0.01 + drop * frac
    return jnp.asarray(u)


def test_the_symmetric_crawler_is_its_own_mirror_image():
    cm, perm, off = _crawler()
    assert off < 1e-12  # every node has a mirror node
    assert sorted(perm) == list(range(len(perm))) and np.all(perm[perm] == np.arange(len(perm)))
    assert perm[cm.left] == cm.right and perm[cm.tips[0]] == cm.tips[1]


@functools.cache
def _forces():
    """One compiled program: each term's forces and committed state, the internal force
    and M u, at a state ``u`` with anchors from ``u_anchor`` (op by op it took 50 s)."""
    cm, _, _ = _crawler()
    m = cm.model
    p, topo = m.params, m.topology

    @jax.jit
    def fn(u, u_anchor):
        zero = jnp.zeros_like(u)
        out = []
        for term, pe in zip(m.terms, p.extra, strict=True):
            h = term.history_at(u_anchor, pe)
            c = term.commit(u, zero, 0.0, h, pe)
            out.append((term.residual(u, zero, 0.0, h, pe), c.p_n, c.f_t, c.dissipation, c.state))
        return out, assembly.internal_force(u, p, topo), assembly.mass_times(u, p, topo)

    return fn


#: (shift, drop, seed) of the random states: bristles bent towards (+) or away from (-)
#: the land edges, pressed in by ``drop`` (mm) at the tip.
CASES = [(0.6, 0.1, 0), (-0.3, 0.2, 1), (0.45, 0.05, 2), (-0.6, 0.2, 3)]


def _case(shift, drop, seed):
    cm, _, _ = _crawler()
    rng = np.random.default_rng(seed)
    u_anchor = _state(cm, rng, shift, drop, 0.05)
    u = u_anchor + _state(cm, rng, 0.0, 0.0, 0.03) * jnp.asarray([1.0, 0.0, 1.0])
    return u, u_anchor


@pytest.mark.slow
def test_the_cases_load_both_terms_in_stick_and_in_slip():
    # Together the cases put points of each contact term in stick and in slip, so the
    # mirror test below covers both branches of the return mapping in both terms.
    states = [set(), set()]
    for case in CASES:
        for seen, term in zip(states, _forces()(*_case(*case))[0], strict=True):
            seen |= set(np.ravel(np.asarray(term[4])).tolist())
    assert all({STICK, SLIP} <= seen for seen in states)


@pytest.mark.slow
@pytest.mark.parametrize("shift, drop, seed", CASES)
def test_forces_commute_with_the_mirror(shift, drop, seed):
    _, perm, _ = _crawler()
    u, u_anchor = _case(shift, drop, seed)
    terms, f_int, Mu = _forces()(u, u_anchor)
    terms_m, f_int_m, Mu_m = _forces()(_mirror(u, perm), _mirror(u_anchor, perm))
    loaded = 0
    for (f, p_n, f_t, diss, _), (f_m, p_n_m, f_t_m, diss_m, _) in zip(terms, terms_m, strict=True):
        size = float(jnp.max(jnp.abs(f)))
        loaded += size > 1.0
        np.testing.assert_allclose(f_m, _mirror(f, perm), atol=1e-11 * max(size, 1.0))
        # The committed contact state is the mirror image too: the same normal forces,
        # friction forces and dissipation, point for point up to the relabelling.
        for a, b in ((p_n, p_n_m), (np.abs(f_t), np.abs(f_t_m))):
            np.testing.assert_allclose(np.sort(np.ravel(b)), np.sort(np.ravel(a)), atol=1e-10)
        np.testing.assert_allclose(np.sum(diss_m), np.sum(diss), atol=1e-12)
    # Both contact terms carry load in these states (the test is not vacuous).
    assert loaded == 2
    np.testing.assert_allclose(f_int_m, _mirror(f_int, perm), atol=1e-9)
    np.testing.assert_allclose(Mu_m, _mirror(Mu, perm), atol=1e-15)
