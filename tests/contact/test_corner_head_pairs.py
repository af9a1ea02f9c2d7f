"""The corner term evaluates its first ``head_pairs`` differentiated pairs per outline and
the others only where one of them may touch: the residual and its Newton tangent must be
those of evaluating all of them, whether the others touch or not."""

import dataclasses
import functools
import math

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from bristlecrawler import fe
from bristlecrawler.contact import CoulombLaw, Grooves
from bristlecrawler.contact.corner import FaceCornerContact, beam_outline

LAW = CoulombLaw.for_reference_load(0.5, load=1.0)
THICK = 0.5


def _strip(theta):
    """A strip 6 mm long and 0.5 mm thick over grooves 1 mm wide every 2 mm (land edges
    rounded to 0.02 mm), turned by ``theta`` about its left end and lowered until it
    presses 2 um into the corners it reaches: (term, u, history, params)."""
    s = fe.Structure()
    a = s.node(0.0, 0.5 * THICK)
    sec = fe.TaperedRect(E=1.0, b=1.0, h0=THICK, h1=THICK, rho=1e-9, nu=0.3)
    nodes = s.chain(a, (6.0, 0.5 * THICK), 12, sec)
    outline, off = beam_outline(nodes, np.full(len(nodes), THICK), (0.0, 1.0))
    term = FaceCornerContact((outline,), 6)
    sub = Grooves(width=1.0, depth=0.25, pitch=2.0, phase=0.25, fillet_top=0.02)
    X = np.asarray(s._X)[:, :2]
    p = FaceCornerContact.params(np.asarray(s._X), (outline,), [off], sub, LAW)
    c, sn = math.cos(theta), math.sin(theta)
    x = (X - X[0]) @ np.array([[c, -sn], [sn, c]]).T + X[0]
    u = np.zeros((len(X), 3))
    u[:, :2] = x - X
    u[:, 2] = theta
    for _ in range(4):
        u[:, 1] -= float(jnp.min(_gaps(term)(jnp.asarray(u), p))) + 2e-3
    u = jnp.asarray(u)
    return term, u, _history(term)(u, p), p


@functools.cache
def _gaps(term):
    return jax.jit(lambda u, p: term._gs(u, term._k0(u, p), p)[0])


@functools.cache
def _history(term):
    """The fresh history at u with the statuses its commit gives (closed pairs stick)."""

    def history(u, p):
        h = term.history_at(u, p)
        return dataclasses.replace(h, state=term.commit(u, u, 0.0, h, p).state)

    return jax.jit(history)


@functools.cache
def _forces_and_tangents(term):
    """One compiled program: the forces and dense tangents of ``term`` with one, two and
    all four of its differentiated pairs evaluated first."""
    variants = [dataclasses.replace(term, head_pairs=k) for k in (term.tangent_pairs, 1, 2)]

    def both(u, h, p):
        out = []
        for t in variants:
            f = lambda u, t=t: t.residual(u, jnp.zeros_like(u), 0.0, h, p)  # noqa: E731
            out.append((f(u), jax.jacfwd(f)(u)))
        return out

    return jax.jit(both)


@pytest.mark.slow
@pytest.mark.parametrize("theta", [0.0, -0.3])
def test_head_pairs_give_the_forces_and_tangent_of_all_pairs(theta):
    """Flat on the lands the strip closes more pairs than two (the others are evaluated);
    tilted it closes one (they are skipped): either way, one or two head pairs give the
    forces and the dense tangent of evaluating all four."""
    term, u, h, p = _strip(theta)
    closed = int(np.sum(np.asarray(h.state) != 0))
    assert (closed > 2) if theta == 0.0 else (1 <= closed <= 2)
    (f_ref, K_ref), *heads = _forces_and_tangents(term)(u, h, p)
    f_ref, K_ref = np.asarray(f_ref), np.asarray(K_ref)
    assert np.abs(f_ref).max() > 0.0
    for f, K in heads:
        np.testing.assert_allclose(f, f_ref, rtol=0, atol=1e-12 * np.abs(f_ref).max())
        np.testing.assert_allclose(K, K_ref, rtol=0, atol=1e-10 * np.abs(K_ref).max())


def test_head_pairs_must_be_positive():
    term, *_ = _strip(0.0)
    with pytest.raises(Exception, match="head_pairs"):
        dataclasses.replace(term, head_pairs=0)
