"""The exported decks, read back by an independent reader: what they hold is the spec's."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from bristlecrawler.contact.profile import profile_chain
from bristlecrawler.contact.substrates import Flat, Grooves, Sawtooth
from bristlecrawler.crawler.drag import DragTest
from bristlecrawler.crawler.model import weight_share
from bristlecrawler.crawler.spec import Actuation, Bristle, CrawlerSpec
from bristlecrawler.errors import InputError
from bristlecrawler.export import ContinuumOptions, continuum_deck, crawler_deck, drag_beam_deck
from bristlecrawler.export.crawler_deck import stroke_table
from bristlecrawler.export.geometry import bristle_mesh, outline, polyline, skin

from .deck_parser import amplitude, elements, find, nodes, parse

PAPER = CrawlerSpec.paper()


def _areas(points, quads):
    x, y = points[quads, 0], points[quads, 1]
    return 0.5 * np.sum(x * np.roll(y, -1, axis=1) - np.roll(x, -1, axis=1) * y, axis=1)


@settings(max_examples=40, deadline=None)
@given(
    alpha=st.floats(-79.0, 79.0),
    length=st.floats(1.0, 20.0),
    h0=st.floats(0.2, 5.0),
    h1=st.floats(0.1, 5.0),
    along=st.integers(1, 30),
    across=st.integers(1, 6),
)
def test_the_bristle_mesh_fills_the_tapered_bristle(alpha, length, h0, h1, along, across):
    b = Bristle(alpha_deg=alpha, length=length, thickness_clamp=h0, thickness_tip=h1)
    m = bristle_mesh(b, (0.0, 0.0), along, across)
    a = _areas(m.points, m.elements[:, :4])
    assert np.all(a > 0)  # counter-clockwise, whichever way the bristle leans
    # A trapezoid: the area is the length times the mean thickness, exactly.
    assert a.sum() == pytest.approx(length * 0.5 * (h0 + h1), rel=1e-10)
    # Each mid-side node halves its face.
    p = m.points[m.elements]
    for k in range(4):
        assert np.allclose(p[:, 4 + k], 0.5 * (p[:, k] + p[:, (k + 1) % 4]))
    assert len(np.unique(m.elements)) == len(m.points)  # no node left unconnected
    tip = m.points[m.station(along)].mean(axis=0)
    assert tip == pytest.approx([-length * math.sin(b.alpha), -length * math.cos(b.alpha)])


@settings(max_examples=30, deadline=None)
@given(
    width=st.floats(0.3, 1.5),
    land=st.floats(0.3, 2.0),
    depth=st.floats(0.1, 1.0),
    top=st.floats(0.0, 0.49),
    bottom=st.floats(0.0, 0.49),
)
def test_the_outline_has_the_contact_models_arc_length(width, land, depth, top, bottom):
    """The fillets drawn as arcs give one period the arc length of the contact model's own
    profile chain (segments and fillets)."""
    pitch = width + land
    rt = top * min(0.5 * width, 0.5 * land, 0.5 * depth)
    rb = bottom * min(0.5 * width, 0.5 * depth)
    g = Grooves(width=width, depth=depth, pitch=pitch, fillet_top=rt, fillet_bottom=rb)
    o = outline(g)
    p = polyline(o, 0.0, 3 * pitch, arc_points=400, max_step=0.01)
    x0 = o.start[0] + math.ceil((p[0, 0] - o.start[0]) / pitch) * pitch
    inside = (p[:, 0] >= x0 - 1e-12) & (p[:, 0] <= x0 + pitch + 1e-12)
    seg = p[inside]
    length = np.sum(np.linalg.norm(np.diff(seg, axis=0), axis=1))
    assert length == pytest.approx(float(profile_chain(g.profile()).length), rel=2e-4)


def test_a_surface_layer_thicker_than_a_fillet_is_refused():
    g = Grooves(width=1.0, depth=0.25, pitch=2.0, fillet_top=0.02)
    pts = polyline(outline(g), 0.0, 4.0)
    with pytest.raises(InputError, match="folds over itself"):
        skin(pts, 0.1)
    nodes_, quads = skin(pts, 0.005)
    assert np.all(_areas(nodes_, quads) > 0)


@pytest.mark.parametrize("plane, kind", [("stress", "CPS8"), ("strain", "CPE8")])
def test_the_continuum_deck_holds_the_spec(plane, kind):
    test = DragTest(direction="cycle", distance=4.0, legs=2)
    opts = ContinuumOptions(plane=plane, along=12, across=3)
    text, info = continuum_deck(PAPER, test, opts)
    blocks = parse(text)
    b = PAPER.bristles[0]
    bristle = elements(blocks, kind)
    substrate = elements(blocks, kind[:3] + "4")
    assert len(bristle) == 12 * 3
    assert len(nodes(blocks)) == info.nodes
    assert len(bristle) + len(substrate) == info.elements
    # A slice of the bristle: its sections' thickness, its forces the bristle's over b / t.
    sections = find(blocks, "SOLID SECTION")
    assert {float(s.rows[0][0]) for s in sections} == {info.slice}
    assert info.force_scale == pytest.approx(b.width / info.slice)
    (mat,) = [i for i, blk in enumerate(blocks) if blk.keyword == "MATERIAL"][:1]
    assert blocks[mat + 1].numbers()[0] == [b.youngs_modulus, b.poisson_ratio]
    # The load is the bristle's weight share, the path the test's, after a 1 s load step.
    (cload,) = find(blocks, "CLOAD")
    assert float(cload.rows[0][2]) * info.force_scale == pytest.approx(-weight_share(PAPER))
    t, x = amplitude(blocks, "CARRIAGE_PATH")
    tp, xp = test.path()
    assert np.allclose(t, tp + 1.0) and np.allclose(x, xp)
    (friction,) = find(blocks, "FRICTION")
    assert float(friction.rows[0][0]) == PAPER.contact.mu


def test_the_continuum_bristle_touches_the_surface_under_its_tip():
    """Its lowest point sits PENETRATION0 into the surface below it, wherever the tip is."""
    for phase in (0.0, 0.7, 1.3):
        spec = dataclasses.replace(
            PAPER, substrate=Grooves(width=1.0, depth=0.25, pitch=2.0, phase=phase)
        )
        text, _ = continuum_deck(spec, DragTest(), ContinuumOptions(along=8, across=2))
        blocks = parse(text)
        pts = nodes(blocks)
        bristle = np.array([pts[n] for n in pts if n < 100001])
        low = bristle[np.argmin(bristle[:, 1])]
        surf = np.array([pts[n] for n in pts if n >= 100001])
        k = len(surf) // 2
        level = np.interp(low[0], surf[:k, 0], surf[:k, 1])
        assert low[1] == pytest.approx(level - 1e-3, abs=1e-9)


def test_the_beam_deck_has_a_section_per_element_at_its_mean_thickness():
    text, _ = drag_beam_deck(PAPER, DragTest())
    blocks = parse(text)
    b = PAPER.bristles[0]
    beams = elements(blocks, "B21")
    assert len(beams) == b.elements
    sections = find(blocks, "BEAM SECTION")
    h = [float(s.rows[0][1]) for s in sections]
    expect = b.thickness((np.arange(b.elements) + 0.5) / b.elements)
    assert np.allclose(h, expect)
    assert all(float(s.rows[0][0]) == b.width for s in sections)
    # The rigid surface: a START, then lines and the fillet arcs, all reaching one level.
    (surf,) = find(blocks, "SURFACE", type="SEGMENTS")
    assert surf.rows[0][0] == "START"
    arcs = [r for r in surf.rows if r[0] == "CIRCL"]
    assert arcs and {r[0] for r in surf.rows[1:]} <= {"LINE", "CIRCL"}
    (dyn,) = find(blocks, "DYNAMIC")[:1]
    assert float(dyn.params["ALPHA"]) == PAPER.solver.hht_alpha


def test_the_crawler_deck_holds_the_bodys_parts_and_the_stroke():
    spec = PAPER.with_bristles(3)
    text, info = crawler_deck(spec)
    blocks = parse(text)
    assert len(elements(blocks, "CONN2D2")) == 2
    assert len(elements(blocks, "B21")) == sum(b.elements for b in spec.bristles)
    (mass,) = find(blocks, "MASS", elset="BODY_MASSES")
    assert 3 * float(mass.rows[0][0]) == pytest.approx(spec.body.mass)
    assert len(find(blocks, "MPC")) == 3
    for j in range(2):
        t, v = amplitude(blocks, f"STROKE_{j}")
        a = spec.actuation
        s = a.s_max * np.sin(np.pi * (np.asarray(t) - a.settle_time) / a.period) ** 2
        s[np.asarray(t) < a.settle_time] = 0.0
        assert np.allclose(v, -s, atol=1e-9)
        assert t[-1] == pytest.approx(a.settle_time + a.cycles * a.period)
    steps = find(blocks, "DYNAMIC")
    assert [float(s.rows[0][1]) for s in steps] == [info.settle, info.stroke_time]


def test_a_peristaltic_strokes_amplitudes_start_late():
    spec = dataclasses.replace(
        PAPER.with_bristles(3), actuation=Actuation(gait="peristaltic", lag=2.0, cycles=1)
    )
    t0, _ = stroke_table(spec, 0)
    t1, v1 = stroke_table(spec, 1)
    assert t1[1] == pytest.approx(t0[1] + 2.0) and v1[0] == v1[1] == 0.0


def test_a_history_too_long_for_an_amplitude_table_is_refused():
    t = np.linspace(0.0, 100.0, 20001)
    spec = dataclasses.replace(PAPER, actuation=Actuation(history=(tuple(t), tuple(0 * t))))
    with pytest.raises(InputError, match="more than this export writes"):
        crawler_deck(spec)


@pytest.mark.parametrize("substrate", [Flat(), Sawtooth(pitch=2.0, height=0.3)])
def test_other_substrates_export(substrate):
    spec = dataclasses.replace(PAPER, substrate=substrate)
    text, info = continuum_deck(spec, DragTest(distance=2.0), ContinuumOptions(along=8, across=2))
    assert info.elements > 16 and "*CONTACT PAIR" in text
    assert "*RIGID BODY" in drag_beam_deck(spec, DragTest(distance=2.0))[0]
