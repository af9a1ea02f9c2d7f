"""Input decks of a drag test: one bristle of a design, clamped to a carriage, over the texture.

The same test as :func:`crawler.drag.drag_test`: the carriage carries the bristle's share
of the crawler's weight, is free vertically, holds the clamp's rotation and follows the
test's horizontal path; the bristle has the design's taper, material and friction.

Two forms:

* **beam** (:func:`beam_deck`): B21 beam elements, one section per element at its mean
  thickness, the substrate an analytical rigid surface with its fillets as arcs; the
  paper's own model. The dialect's 2-D beams and analytical surfaces are ABAQUS's:
  CalculiX does not run this deck.
* **continuum** (:func:`continuum_deck`): the bristle as plane-stress (CPS8) or
  plane-strain (CPE8) quadratic quadrilaterals, the substrate a layer of elements under
  its surface held in place, surface-to-surface penalty contact with Coulomb friction;
  ABAQUS and CalculiX run it. The model is a slice of the bristle, ``SLICE`` of its
  thinnest section thick: CalculiX expands plane elements into bricks of the section's
  thickness, and a brick as wide as the bristle bends as a plate (E / (1 - nu^2)), not
  as plane stress. Every force of the slice (the load, the reactions) is the whole
  bristle's times the slice's thickness over the width b (:attr:`DeckInfo.force_scale`).

Both decks are quasi-static: a load step (the weight on the clamp and the bristle's own
weight), then the carriage's path as an amplitude over a static step whose time is the
path's (s), so the path's times are the test's.
"""

from __future__ import annotations

import dataclasses
import itertools
import math
from dataclasses import dataclass
from typing import Literal

import numpy as np

from bristlecrawler.crawler.drag import DragTest
from bristlecrawler.crawler.model import weight_share
from bristlecrawler.crawler.spec import Bristle, CrawlerSpec
from bristlecrawler.errors import InputError
from bristlecrawler.export.deck import Deck
from bristlecrawler.export.geometry import bristle_mesh, outline, polyline, skin

#: Initial overlap of the tip and the surface, mm (the FE model's, :mod:`crawler.model`).
PENETRATION0 = 1e-3
#: Node labels of the substrate start here (the bristle's are below).
SUBSTRATE_FIRST = 100001
#: Thickness of the modelled slice over the bristle's thinnest section.
SLICE = 0.02


@dataclass(frozen=True)
class ContinuumOptions:
    """Discretisation of the continuum deck.

    Attributes:
        plane: "stress" (a narrow bristle: the beam's E) or "strain" (a wide one:
            E / (1 - nu^2) in bending).
        along: 8-node elements along the bristle.
        across: 8-node elements through its thickness.
        skin: thickness of the substrate's layer of elements, mm; None: a quarter of the
            smallest fillet radius (or 0.02 mm without fillets).
        contact_length: the last this many mm of each face (and the tip's end face) can
            touch the substrate, mm.
        increments: largest number of increments of each step.
    """

    plane: Literal["stress", "strain"] = "stress"
    along: int = 20
    across: int = 3
    skin: float | None = None
    contact_length: float = 1.5
    increments: int = 2000


@dataclass(frozen=True)
class DeckInfo:
    """What a deck holds, for the parsers and the tests: the load on the clamp (N), the
    bristle's own weight (N), the path's knots (s, mm), the start of the path (s), the
    node and element counts, the bristle's width b (mm) and the thickness of the
    modelled slice (mm; 0: the whole width)."""

    load: float
    bristle_weight: float
    path: tuple[np.ndarray, np.ndarray]
    settle: float
    nodes: int
    elements: int
    width: float
    slice: float = 0.0

    @property
    def force_scale(self) -> float:
        """The whole bristle's force over the slice's (b / slice; 1 for a beam deck)."""
        return self.width / self.slice if self.slice else 1.0


def _carriage_path(test: DragTest) -> tuple[np.ndarray, np.ndarray]:
    t, x = test.path()
    return np.asarray(t, dtype=float), np.asarray(x, dtype=float)


def _check(spec: CrawlerSpec, test: DragTest) -> None:
    spec.check()
    test.check(spec)
    t, _ = _carriage_path(test)
    if len(t) > 10000:
        raise InputError(
            f"the carriage's path has {len(t)} knots, more than an amplitude table of this "
            "export holds (10000): shorten the test (fewer legs or a shorter distance)"
        )


def _surface_height(points: np.ndarray, x: float) -> float:
    """Height of the surface polyline above ``x`` (its highest crossing), mm."""
    ys = []
    for (x0, y0), (x1, y1) in itertools.pairwise(points):
        if min(x0, x1) <= x <= max(x0, x1):
            ys.append(max(y0, y1) if x1 == x0 else y0 + (y1 - y0) * (x - x0) / (x1 - x0))
    if not ys:
        raise InputError(f"the substrate's outline does not reach x = {x:g} mm")
    return max(ys)


def _placement(spec: CrawlerSpec, test: DragTest, surface: np.ndarray):
    """The bristle's clamp (x, y), mm: its tip's lower corner just touching the surface."""
    b = spec.bristles[test.bristle]
    n = b.normal()
    tip_axis = np.array([-b.length * math.sin(b.alpha), -b.length * math.cos(b.alpha)])
    corners = [tip_axis + s * 0.5 * b.thickness_tip * n for s in (1.0, -1.0)]
    low = min(corners, key=lambda c: c[1])
    level = _surface_height(surface, float(low[0]))
    return np.array([0.0, level - PENETRATION0 - low[1]])


def _skin_depth(spec: CrawlerSpec, opts: ContinuumOptions) -> float:
    if opts.skin is not None:
        return float(opts.skin)
    prof = spec.substrate.profile()
    r = np.asarray(prof.fillets, dtype=float)
    r = r[r > 0]
    return 0.25 * float(r.min()) if r.size else 0.02


def _surface_span(spec: CrawlerSpec, test: DragTest, clamp_x: float) -> tuple[float, float]:
    b = spec.bristles[test.bristle]
    _, x = _carriage_path(test)
    reach = b.length + b.thickness_clamp
    return clamp_x + float(x.min()) - reach - 1.0, clamp_x + float(x.max()) + reach + 1.0


def continuum_deck(
    spec: CrawlerSpec, test: DragTest | None = None, options: ContinuumOptions | None = None
) -> tuple[str, DeckInfo]:
    """The drag test of ``spec``'s bristle as a continuum deck (CalculiX and ABAQUS)."""
    test = test or DragTest()
    opts = options or ContinuumOptions()
    _check(spec, test)
    if opts.plane not in ("stress", "strain"):
        raise InputError(f"plane must be 'stress' or 'strain', got {opts.plane!r}")
    b = spec.bristles[test.bristle]
    load = test.load or weight_share(spec)
    x0, x1 = _surface_span(spec, test, 0.0)
    surface = polyline(outline(spec.substrate), x0, x1)
    clamp = _placement(spec, test, surface)
    mesh = bristle_mesh(b, tuple(clamp), opts.along, opts.across)
    sub_nodes, sub_quads = skin(surface, _skin_depth(spec, opts))
    thick = SLICE * min(b.thickness_clamp, b.thickness_tip)
    d = Deck(
        f"bristlecrawler drag test of {spec.name}, bristle {test.bristle}: continuum "
        f"(plane {opts.plane}), alpha {b.alpha_deg:g} deg, mu {spec.contact.mu:g}, "
        f"load {load:.6g} N; units mm, N, s, t"
    )
    d.comment(
        "Generated by bristlecrawler from a CrawlerSpec; do not edit by hand, export again.\n"
        f"A slice {thick:.6g} mm thick of the bristle's {b.width:g} mm width: multiply its "
        f"forces by {b.width / thick:.8g}."
    )
    bristle = d.nodes(1, mesh.points, nset="BRISTLE_NODES")
    subst = d.nodes(SUBSTRATE_FIRST, sub_nodes, nset="SUBSTRATE_NODES")
    kind = "CPS8" if opts.plane == "stress" else "CPE8"
    d.elements(kind, 1, bristle[mesh.elements], "BRISTLE")
    # The substrate is held in place: bilinear elements of the same plane state give its faces.
    d.elements(kind[:3] + "4", SUBSTRATE_FIRST, subst[sub_quads], "SUBSTRATE")
    clamp_nodes = bristle[mesh.station(0)]
    d.labels("NSET", "CLAMP", clamp_nodes)
    d.labels("NSET", "CARRIAGE", clamp_nodes[:1])
    d.labels("NSET", "TIP", bristle[mesh.station(mesh.along)])
    _contact_sets(d, mesh, b, opts)
    _materials(d, b, thick)
    _contact_definition(d, spec, load, b.width * b.thickness_tip)
    _clamp_constraints(d, clamp_nodes)
    t, x = _carriage_path(test)
    _steps(d, spec, load * thick / b.width, t, x, opts)
    info = DeckInfo(
        load=load,
        bristle_weight=b.mass * spec.gravity,
        path=(t, x),
        settle=1.0,
        nodes=len(bristle) + len(subst),
        elements=len(mesh.elements) + len(sub_quads),
        width=b.width,
        slice=thick,
    )
    return d.text(), info


def _contact_sets(d: Deck, mesh, b, opts: ContinuumOptions) -> None:
    """The bristle's element faces that may touch (slave: both faces over the last
    ``contact_length`` mm and the tip's end face) and the substrate's surface (master)."""
    near = min(mesh.along, max(1, math.ceil(opts.contact_length / b.length * mesh.along)))
    w = mesh.across
    flipped = mesh.flipped
    rows = {"S1": [], "S2": [], "S3": []}
    for i in range(mesh.along - near, mesh.along):
        lo, hi = i * w, i * w + w - 1  # the elements of this station on the -n and +n faces
        rows["S3" if flipped else "S1"].append(lo + 1)
        rows["S1" if flipped else "S3"].append(hi + 1)
    rows["S2"] = [(mesh.along - 1) * w + j + 1 for j in range(w)]
    for face, elems in rows.items():
        d.labels("ELSET", f"TIP_{face}", elems)
    d.keyword("SURFACE", name="BRISTLE_TIP", type="ELEMENT")
    for face in rows:
        d.data(f"TIP_{face}", face)
    d.keyword("ELSET", elset="SUBSTRATE_TOP")
    d.data("SUBSTRATE")
    d.keyword("SURFACE", name="SUBSTRATE_SURFACE", type="ELEMENT")
    d.data("SUBSTRATE_TOP", "S4")


def _materials(d: Deck, b, thick: float, substrate: bool = True) -> None:
    d.keyword("MATERIAL", name="SILICONE")
    d.keyword("ELASTIC")
    d.data(b.youngs_modulus, b.poisson_ratio)
    d.keyword("DENSITY")
    d.data(b.density)
    d.keyword("SOLID SECTION", elset="BRISTLE", material="SILICONE")
    d.data(thick)
    if not substrate:
        return
    # The substrate is held in place node by node: its stiffness only keeps the
    # elements' equations regular.
    d.keyword("MATERIAL", name="SUBSTRATE")
    d.keyword("ELASTIC")
    d.data(1000.0 * b.youngs_modulus, 0.3)
    d.keyword("DENSITY")
    d.data(b.density)
    d.keyword("SOLID SECTION", elset="SUBSTRATE", material="SUBSTRATE")
    d.data(thick)


def coulomb_mu(spec: CrawlerSpec) -> float:
    """The spec's Coulomb coefficient, which ``*FRICTION`` takes; InputError for another
    friction law (the decks have no counterpart of it)."""
    if spec.contact.friction != "coulomb":
        raise InputError(
            f"the decks write Coulomb friction (*FRICTION); contact.friction = "
            f"{spec.contact.friction} has no counterpart there"
        )
    return spec.contact.mu


def _contact_definition(d: Deck, spec: CrawlerSpec, load: float, area: float) -> None:
    """Penalty contact sized as the FE model's: 1e-3 mm of penetration and the stick
    drift at the reference load, spread over ``area`` (mm^2), the tip's end face."""
    c = spec.contact
    mu = coulomb_mu(spec)
    ref = c.penalty_load or load
    d.keyword("SURFACE INTERACTION", name="BRISTLE_SUBSTRATE")
    d.keyword("SURFACE BEHAVIOR", **{"pressure-overclosure": "LINEAR"})
    d.data(ref / (PENETRATION0 * area), 0.0, 0.0)
    if mu > 0:
        d.keyword("FRICTION")
        d.data(mu, mu * ref / (c.stick_drift * area))
    d.keyword("CONTACT PAIR", interaction="BRISTLE_SUBSTRATE", type="SURFACE TO SURFACE")
    d.data("BRISTLE_TIP", "SUBSTRATE_SURFACE")


def _clamp_constraints(d: Deck, clamp_nodes) -> None:
    """The clamp's face moves as one (its rotation held): every node's vertical motion
    equals the carriage node's; the horizontal one is prescribed on all of them."""
    ref = int(clamp_nodes[0])
    d.keyword("EQUATION")
    for n in clamp_nodes[1:]:
        d.data(2)
        d.data(int(n), 2, 1.0, ref, 2, -1.0)
    d.keyword("BOUNDARY")
    d.data("SUBSTRATE_NODES", 1, 2)


def _steps(d: Deck, spec: CrawlerSpec, load: float, t, x, opts: ContinuumOptions) -> None:
    duration = float(t[-1])
    d.keyword("AMPLITUDE", name="CARRIAGE_PATH", time="TOTAL TIME")
    rows = [(1.0 + float(ti), float(xi)) for ti, xi in zip(t, x, strict=True)]
    for i in range(0, len(rows), 4):
        d.data(*(v for row in rows[i : i + 4] for v in row))
    # Step 1: the weight. Step 2: the path (its times follow the first step's second).
    d.keyword("STEP", nlgeom=True, inc=opts.increments)
    d.keyword("STATIC")
    d.data(0.05, 1.0, 1e-6, 0.25)
    d.keyword("BOUNDARY")
    d.data("CLAMP", 1, 1, 0.0)
    d.keyword("CLOAD")
    d.data("CARRIAGE", 2, -load)
    if spec.gravity > 0:
        d.keyword("DLOAD")
        d.data("BRISTLE", "GRAV", spec.gravity, 0.0, -1.0, 0.0)
    _outputs(d)
    d.keyword("END STEP")
    d.keyword("STEP", nlgeom=True, inc=opts.increments)
    d.keyword("STATIC")
    d.data(min(0.01, duration / 100), duration, duration * 1e-7, min(0.02, duration / 20))
    d.keyword("BOUNDARY", amplitude="CARRIAGE_PATH")
    d.data("CLAMP", 1, 1, 1.0)
    _outputs(d)
    d.keyword("END STEP")


def _outputs(d: Deck) -> None:
    d.keyword("NODE PRINT", nset="CLAMP", totals="ONLY")
    d.data("RF")
    d.keyword("NODE PRINT", nset="CARRIAGE")
    d.data("U")
    d.keyword("NODE PRINT", nset="SUBSTRATE_NODES", totals="ONLY")
    d.data("RF")
    d.keyword("NODE PRINT", nset="TIP")
    d.data("U")
    d.keyword("NODE FILE")
    d.data("U", "RF")


def crosscheck_spec(spec: CrawlerSpec, test: DragTest, share: float = 0.5) -> CrawlerSpec:
    """``spec`` with its grooves shifted so that the tested bristle's tip lands on a groove
    bottom, ``share`` of the way from the groove's left wall to its right one (the
    cross-check drags it along the bottom into the right wall). Other substrates as they
    are."""
    from bristlecrawler.contact.substrates import Grooves

    sub = spec.substrate
    if not isinstance(sub, Grooves):
        return spec
    b = spec.bristles[test.bristle]
    n = b.normal()
    tip = np.array([-b.length * math.sin(b.alpha), 0.0])
    low = min((tip + s * 0.5 * b.thickness_tip * n for s in (1.0, -1.0)), key=lambda c: c[1])
    width = float(sub.width)
    phase = float(low[0]) - share * width
    return dataclasses.replace(spec, substrate=dataclasses.replace(sub, phase=phase))


def tip_compliance_deck(
    b: Bristle, options: ContinuumOptions | None = None, force: float = 1e-3
) -> tuple[str, float]:
    """A linear deck of the bristle alone: its clamp's face held, a horizontal force
    ``force`` (N, the whole bristle's) spread over the tip's end face; returns the deck and
    the slice's force scale. The tip's mean horizontal displacement over ``force`` is the
    elastic compliance that a beam model gives as its tip's (mm/N)."""
    opts = options or ContinuumOptions()
    mesh = bristle_mesh(b, (0.0, 0.0), opts.along, opts.across)
    thick = SLICE * min(b.thickness_clamp, b.thickness_tip)
    d = Deck(f"bristlecrawler: elastic tip compliance of a bristle, plane {opts.plane}")
    labels = d.nodes(1, mesh.points, nset="BRISTLE_NODES")
    d.elements("CPS8" if opts.plane == "stress" else "CPE8", 1, labels[mesh.elements], "BRISTLE")
    d.labels("NSET", "CLAMP", labels[mesh.station(0)])
    tip = labels[mesh.station(mesh.along)]
    d.labels("NSET", "TIP", tip)
    _materials(d, b, thick, substrate=False)
    d.keyword("BOUNDARY")
    d.data("CLAMP", 1, 2)
    d.keyword("STEP")
    d.keyword("STATIC")
    d.keyword("CLOAD")
    share = force * thick / b.width / len(tip)
    for n in tip:
        d.data(int(n), 1, share)
    d.keyword("NODE PRINT", nset="TIP")
    d.data("U")
    d.keyword("END STEP")
    return d.text(), b.width / thick
