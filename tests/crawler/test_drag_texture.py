"""The texture law read from a drag test: the reduced bristle's own law read back (the
FE bristle's law on grooves is tested in test_drag.py, on the drag run its tests
share)."""

import dataclasses
import functools

import numpy as np
import pytest

from bristlecrawler.crawler.drag_analysis import DragResult
from bristlecrawler.crawler.drag_texture import texture_law
from bristlecrawler.errors import InputError
from bristlecrawler.results.texture import TextureLaw

FP = np.array([0.30, 0.28, 0.25, 0.27, 0.22, 0.20, 0.24, 0.26])
FN = np.array([0.45, 0.40, 0.35, 0.38, 0.50, 0.42, 0.33, 0.36])


def _slide(law, xi, force_at, direction):
    """Move a tip at ``xi`` in ``direction`` while its spring force (``force_at(xi)``,
    pulling that way) exceeds the resistance of the cell it enters; returns xi."""
    for _ in range(1000):
        f = direction * force_at(xi)
        if direction > 0:
            r, edge = float(law.forward_resistance(xi)), float(law.next_edge(xi, 1))
        else:
            r, edge = float(law.backward_resistance(xi)), float(law.next_edge(xi, -1))
        if f <= r + 1e-15:
            return xi
        stop = xi + direction * (f - r) / law.k_N_per_mm
        if direction * (stop - edge) < 0:
            return stop
        xi = edge
    raise AssertionError("the tip did not settle")


@functools.cache
def _textured_drag(k=2.0, pitch=1.0, legs=3.0, n=3001):
    """A spring of stiffness k (N/mm) whose tip obeys the texture law (FP, FN), dragged
    along by ``legs`` mm and back, quasi-statically, as a drag record."""
    law = TextureLaw(pitch, FP, FN, k)
    x = np.concatenate([np.linspace(0.0, legs, n), np.linspace(legs, 0.0, n)[1:]])
    xi, f, tips, state = 0.01, [], [], []
    for j, xc in enumerate(x):
        d = 1 if j < n else -1
        before = xi
        xi = _slide(law, xi, lambda p, xc=xc: k * (xc + 0.01 - p), d)
        f.append(k * (xc + 0.01 - xi))
        tips.append(xi)
        state.append(2 if xi != before else 1)
    m = x.size
    series = ("elastic", "kinetic", "potential", "friction", "damping", "external")
    return DragResult(
        t=np.arange(m, dtype=float),
        x=x,
        lift=np.zeros(m),
        force_x=np.asarray(f),
        contact=np.zeros((m, 2)),
        tip=np.stack([tips, np.zeros(m)], axis=1),
        tip_state=np.asarray(state),
        energies={name: np.zeros(m) for name in series},
        pitch=pitch,
        load=1.0,
        mu=0.5,
        legs=((0, n - 1, 1), (n - 1, m - 1, -1)),
    )


def test_the_reduced_bristles_own_texture_law_is_read_back():
    """A spring dragged over a texture law (snaps and all) gives back its k and its
    resistance in every cell, both ways, and the tip's offset from the carriage."""
    r = _textured_drag()
    law = texture_law(r, cells=FP.size)
    assert law.k_N_per_mm == pytest.approx(2.0, rel=1e-6)
    np.testing.assert_allclose(law.fp_N, FP, rtol=1e-6)
    np.testing.assert_allclose(law.fn_N, FN, rtol=1e-6)
    assert law.tip_offset_mm == pytest.approx(0.01, abs=1e-9)
    # The summary carries it with units; the dataset as variables over the cells.
    s = r.summary()["texture"]  # at the default 16 cells: each of ours twice
    np.testing.assert_allclose(s["fp_N"], np.repeat(FP, 16 // FP.size), rtol=1e-6)
    ds = r.to_dataset()
    assert ds["texture_fn"].attrs["units"] == "N" and ds["texture_fn"].size == 16
    back = DragResult.from_dataset(ds).texture(cells=FP.size)
    np.testing.assert_allclose(back.fn_N, FN, rtol=1e-6)


def test_a_drag_one_way_gives_no_texture_law():
    r = _textured_drag()
    one = dataclasses.replace(r, legs=r.legs[:1])
    with pytest.raises(InputError, match="against"):
        texture_law(one)
    assert one.summary()["texture"] is None
