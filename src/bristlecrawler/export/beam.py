"""ABAQUS beam decks: the paper's own model of the drag test and of the crawler.

The paper's model (Section 3): B21 beams of variable section for the bristles, the body a
CONN2D2 connector whose length the stroke changes, rigid vertical links down to the
bristles' clamps, two point masses, the textured substrate an analytical rigid surface,
Coulomb friction, a gravity step and a dynamic step with mass-proportional Rayleigh
damping. The decks here write that model from a :class:`CrawlerSpec`: each bristle a
chain of ``elements`` B21 beams with the section of its mean thickness, the body's
segments TRANSLATOR connectors (length changes only, the body turning as one), the links
``*MPC BEAM``, the substrate's profile with its fillets as ``CIRCL`` segments.

B21 beams, CONN2D2 connectors and analytical rigid surfaces are ABAQUS's only: CalculiX
does not run these decks (its continuum deck is :func:`drag_deck.continuum_deck`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from bristlecrawler.crawler.drag import DragTest, first_frequency_estimate
from bristlecrawler.crawler.model import bristle_ends, weight_share
from bristlecrawler.crawler.spec import Bristle, CrawlerSpec
from bristlecrawler.errors import InputError
from bristlecrawler.export.deck import Deck
from bristlecrawler.export.drag_deck import DeckInfo, coulomb_mu
from bristlecrawler.export.geometry import outline

#: Samples of the sin^2 stroke per period in its amplitude table.
STROKE_SAMPLES_PER_PERIOD = 100
#: The most rows an amplitude table of these decks holds.
MAX_AMPLITUDE_ROWS = 10000
#: Node label of the substrate's reference node.
SUBSTRATE_REF = 999999


@dataclass(frozen=True)
class Damping:
    """The Rayleigh coefficients a deck writes: a0 (1/s), a1 (s) and where they came from."""

    a0: float
    a1: float
    source: str


def damping_of(spec: CrawlerSpec, a0: float | None, omega1: float) -> Damping:
    """The deck's Rayleigh damping: the spec's explicit coefficients, the given ``a0``
    (the toolkit's run reports it as ``rayleigh_a0_per_s``), or ``ratio`` at ``omega1``
    (rad/s), an estimate of the first resonance."""
    d = spec.damping
    if d.kind == "explicit":
        return Damping(d.a0, d.a1, "the scenario's explicit a0, a1")
    if a0 is not None:
        if not (math.isfinite(a0) and a0 >= 0):
            raise InputError(f"the damping a0 must be a finite number >= 0 1/s, got {a0}")
        return Damping(a0, 0.0, "given with the export (a run's rayleigh_a0_per_s)")
    coeff = 2.0 * d.ratio * omega1 if d.kind == "mass" else 2.0 * d.ratio / omega1
    how = (
        f"ratio {d.ratio:g} at {omega1 / (2 * math.pi):.4g} Hz, the clamped bristle's first "
        "bending frequency by beam theory (the toolkit takes the settled model's first mode; "
        "pass its rayleigh_a0_per_s to use the same)"
    )
    return Damping(coeff, 0.0, how) if d.kind == "mass" else Damping(0.0, coeff, how)


def analytic_surface(d: Deck, substrate, x0: float, x1: float, y_ref: float) -> None:
    """The substrate's profile over x0..x1 as an analytical rigid surface (solid below)."""
    o = outline(substrate)
    k0 = math.floor((x0 - o.start[0]) / o.period) - 1
    k1 = math.ceil((x1 - o.start[0]) / o.period) + 1
    # ABAQUS puts the solid on the right of the segments' direction for a 2-D surface
    # drawn from START; left to right leaves the substrate below.
    d.keyword("SURFACE", type="SEGMENTS", name="SUBSTRATE")
    d.data("START", *(o.start + np.array([k0 * o.period, 0.0])))
    for k in range(k0, k1):
        shift = np.array([k * o.period, 0.0])
        for piece in o.pieces:
            if piece[0] == "line":
                d.data("LINE", *(piece[1] + shift))
            else:
                d.data("CIRCL", *(piece[1] + shift), *(piece[2] + shift))
    d.keyword("NODE", nset="SUBSTRATE_REF")
    d.data(SUBSTRATE_REF, 0.5 * (x0 + x1), y_ref, 0.0)
    d.keyword("RIGID BODY", **{"analytical surface": "SUBSTRATE", "ref node": SUBSTRATE_REF})


def bristle_chain(d: Deck, b: Bristle, clamp_node: int, clamp_xy, tip_xy, first: int, tag: str):
    """The bristle's nodes (after its clamp node) and B21 elements, one section each."""
    pts = np.linspace(clamp_xy, tip_xy, b.elements + 1)[1:]
    labels = d.nodes(first, pts, nset=f"{tag}_NODES")
    chain = np.concatenate([[clamp_node], labels])
    h = b.thickness((np.arange(b.elements) + 0.5) / b.elements)
    for e in range(b.elements):
        el = f"{tag}_E{e + 1}"
        d.elements("B21", first + e, np.array([[chain[e], chain[e + 1]]]), el)
        d.keyword("BEAM SECTION", elset=el, material=f"{tag}_MATERIAL", section="RECT")
        d.data(b.width, float(h[e]))
        d.data(0.0, 0.0, -1.0)
    return chain


def bristle_material(d: Deck, b: Bristle, tag: str, damping: Damping) -> None:
    d.keyword("MATERIAL", name=f"{tag}_MATERIAL")
    d.keyword("ELASTIC")
    d.data(b.youngs_modulus, b.poisson_ratio)
    d.keyword("DENSITY")
    d.data(b.density)
    if damping.a0 or damping.a1:
        d.keyword("DAMPING", alpha=num(damping.a0), beta=num(damping.a1))


def num(v: float) -> str:
    return f"{float(v):.12g}"


def contact(d: Deck, spec: CrawlerSpec, slave_sets: list[str]) -> None:
    mu = coulomb_mu(spec)
    d.keyword("SURFACE", type="NODE", name="BRISTLES")
    for s in slave_sets:
        d.data(s)
    d.keyword("SURFACE INTERACTION", name="BRISTLE_SUBSTRATE")
    d.keyword("FRICTION")
    d.data(mu)
    d.keyword("CONTACT PAIR", interaction="BRISTLE_SUBSTRATE")
    d.data("BRISTLES", "SUBSTRATE")


def amplitude(d: Deck, name: str, t: np.ndarray, v: np.ndarray) -> None:
    if len(t) > MAX_AMPLITUDE_ROWS:
        raise InputError(
            f"the amplitude {name} needs {len(t)} rows, more than this export writes "
            f"({MAX_AMPLITUDE_ROWS}): fewer cycles or a shorter history"
        )
    d.keyword("AMPLITUDE", name=name, time="TOTAL TIME")
    rows = [(float(a), float(b)) for a, b in zip(t, v, strict=True)]
    for i in range(0, len(rows), 4):
        d.data(*(x for row in rows[i : i + 4] for x in row))


def drag_beam_deck(
    spec: CrawlerSpec, test: DragTest | None = None, a0: float | None = None
) -> tuple[str, DeckInfo]:
    """The drag test of ``spec``'s bristle as the paper's beam model (ABAQUS/Standard)."""
    test = test or DragTest()
    spec.check()
    test.check(spec)
    b = spec.bristles[test.bristle]
    load = test.load or weight_share(spec)
    root, tip = bristle_ends(b, spec.contact, x=0.0)
    settle = spec.actuation.settle_time
    damping = damping_of(spec, a0, 2 * math.pi * first_frequency_estimate(spec, test.bristle))
    d = Deck(
        f"bristlecrawler drag test of {spec.name}, bristle {test.bristle}: B21 beams, "
        f"alpha {b.alpha_deg:g} deg, mu {spec.contact.mu:g}, load {load:.6g} N; units mm, N, s, t"
    )
    d.comment(
        "Generated by bristlecrawler from a CrawlerSpec; do not edit by hand, export again.\n"
        f"Rayleigh damping: {damping.source}."
    )
    d.nodes(1, np.array([root]), nset="CARRIAGE")
    chain = bristle_chain(d, b, 1, root, tip, 2, "BRISTLE")
    d.labels("NSET", "TIP", chain[-1:])
    d.elements("MASS", 900001, np.array([[1]]), "CARRIAGE_MASS")
    if spec.gravity > 0:
        d.keyword("MASS", elset="CARRIAGE_MASS", alpha=num(damping.a0) if damping.a0 else None)
        d.data(load / spec.gravity)
    bristle_material(d, b, "BRISTLE", damping)
    t, x = test.path()
    span = b.length + 2.0
    analytic_surface(d, spec.substrate, float(x.min()) - span, float(x.max()) + span, -1.0)
    contact_set = "BRISTLE_NODES" if spec.contact.nodes == "all" else "TIP"
    contact(d, spec, [contact_set])
    amplitude(d, "CARRIAGE_PATH", np.asarray(t) + settle, np.asarray(x))
    d.keyword("BOUNDARY")
    d.data("SUBSTRATE_REF", 1, 6)
    d.data("CARRIAGE", 6, 6)
    d.data("CARRIAGE", 1, 1)
    dynamic_step(d, spec, settle, "gravity: the weight settles the bristle on the substrate")
    gravity(d, spec, ["CARRIAGE_MASS", *(f"BRISTLE_E{e + 1}" for e in range(b.elements))])
    _drag_outputs(d)
    d.keyword("END STEP")
    dynamic_step(d, spec, float(t[-1]), "drag: the carriage follows its path")
    d.keyword("BOUNDARY", amplitude="CARRIAGE_PATH")
    d.data("CARRIAGE", 1, 1, 1.0)
    _drag_outputs(d)
    d.keyword("END STEP")
    info = DeckInfo(
        load=load,
        bristle_weight=b.mass * spec.gravity,
        path=(np.asarray(t), np.asarray(x)),
        settle=settle,
        nodes=b.elements + 1,
        elements=b.elements + 1,
        width=b.width,
    )
    return d.text(), info


def gravity(d: Deck, spec: CrawlerSpec, elsets: list[str]) -> None:
    if spec.gravity <= 0:
        return
    d.keyword("DLOAD")
    for el in elsets:
        d.data(el, "GRAV", spec.gravity, 0.0, -1.0, 0.0)


def dynamic_step(d: Deck, spec: CrawlerSpec, duration: float, what: str) -> None:
    d.comment(what)
    d.keyword("STEP", nlgeom="YES", inc=1000000)
    d.keyword("DYNAMIC", alpha=num(spec.solver.hht_alpha))
    d.data(min(spec.solver.dt_max, duration), duration, 1e-9, spec.solver.dt_max)


def _drag_outputs(d: Deck) -> None:
    d.keyword("OUTPUT", history=True)
    d.keyword("NODE OUTPUT", nset="CARRIAGE")
    d.data("U1", "U2", "RF1")
    d.keyword("NODE OUTPUT", nset="TIP")
    d.data("U1", "U2")
    d.keyword("ENERGY OUTPUT")
    d.data("ALLWK", "ALLSE", "ALLKE", "ALLFD", "ALLVD")
