"""Assembly of the FE bristle crawler from a :class:`CrawlerSpec` (paper Section 3).

Geometry (x right, y up, mm): one body node above each bristle's clamp, at its position
along the body. The first body node is the master (a rigid body that can translate and
pitch); each next body node is a slave of the one before at the segment's rest length
minus its shortening s_j(t) (the actuators). Rigid vertical links go down from the body
nodes to the clamps; each bristle is a chain of tapered corotational beam elements from
its clamp, inclined by alpha from the vertical with the tip trailing (to the left for
alpha > 0), so every tip starts on the substrate's top level y = 0. The body's mass is
shared equally by its nodes; the bristles' masses come from their density. The tips (or
all bristle nodes) are in frictional contact with the rigid substrate.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

import numpy as np

from bristlecrawler import fe
from bristlecrawler.contact.corner import FaceCornerContact, beam_outline
from bristlecrawler.contact.coulomb import FrictionLaw
from bristlecrawler.contact.term import SubstrateContact
from bristlecrawler.crawler.actuation import DelayedSin2, SampledStretch
from bristlecrawler.crawler.record import observer
from bristlecrawler.crawler.spec import Bristle, CrawlerSpec

#: Initial penetration of the tips, mm: they start just touching the substrate's top.
_PENETRATION0 = 1e-3

LINE_BODY, LINE_LINK, LINE_BRISTLE = 0, 1, 2


@dataclass(frozen=True)
class CrawlerModel:
    """A built crawler: the FE model and the node bookkeeping a run needs.

    Attributes:
        model: the :class:`bristlecrawler.fe.Model`.
        spec: the :class:`CrawlerSpec` it was built from.
        body: body node of each bristle, left to right.
        clamps: clamp node of each bristle.
        bristles: node chain of each bristle, clamp to tip.
        contact: the point-contact term (:class:`contact.SubstrateContact`).
        corners: the corner-to-face term, or None (corner contact off, or a substrate
            without convex corners).
        tip_points: indices among the contact term's points that belong to each tip.
        subtrees: for each body segment, the nodes beyond it (those its actuator pushes).
        lines: line-cell connectivity of the drawing, (C, 2).
        line_kind: :data:`LINE_BODY`, :data:`LINE_LINK` or :data:`LINE_BRISTLE` per cell.
    """

    model: object
    spec: CrawlerSpec
    body: tuple[int, ...]
    clamps: tuple[int, ...]
    bristles: tuple[tuple[int, ...], ...]
    contact: object
    corners: object | None
    tip_points: tuple[tuple[int, ...], ...]
    subtrees: tuple[tuple[int, ...], ...]
    lines: np.ndarray
    line_kind: np.ndarray

    @property
    def tips(self) -> tuple[int, ...]:
        return tuple(chain[-1] for chain in self.bristles)

    @property
    def left(self) -> int:
        return self.body[0]

    @property
    def right(self) -> int:
        return self.body[-1]

    @property
    def contact_params(self):
        """Parameters of the point-contact term (its friction law, substrate, points)."""
        return self.model.params.extra[self.model.terms.index(self.contact)]

    def observer(self):
        """The jitted record of a state (:func:`record.observer`)."""
        return observer(self)

    def node_thickness(self) -> np.ndarray:
        """Section thickness at every node, mm (0 off the bristles)."""
        out = np.zeros(self.model.params.X.shape[0])
        for chain, b in zip(self.bristles, self.spec.bristles, strict=True):
            out[list(chain)] = b.node_thickness()
        return out


def weight(spec: CrawlerSpec) -> float:
    """The crawler's weight (body and bristles), N."""
    return (spec.body.mass + sum(b.mass for b in spec.bristles)) * spec.gravity


def weight_share(spec: CrawlerSpec) -> float:
    """The crawler's weight on one bristle, N: what sizes the contact penalties and what a
    drag test's carriage carries."""
    return weight(spec) / len(spec.bristles)


def bristle_ends(b: Bristle, c, x: float | None = None):
    """Reference positions (mm) of a bristle's clamp and tip, ``((x, y), (x, y))``, with
    the clamp at ``x`` (default: the bristle's position along the body) and the tip's
    contact point on the substrate's top level (:func:`bristle_drop`)."""
    drop, tip_y = bristle_drop(b, c)
    x = b.position if x is None else x
    return (x, drop), (x - b.length * math.sin(b.alpha), tip_y)


def bristle_drop(b: Bristle, c) -> tuple[float, float]:
    """(height of the clamp above the tip's start, height of the tip's axis), mm.

    With surface contact the tip's lower face corner touches the surface, not its axis;
    a disc touches it with its rim."""
    lift = 0.5 * b.thickness_tip * abs(math.sin(b.alpha)) if c.surface else 0.0
    if c.discs and not c.surface:
        lift = 0.5 * b.thickness_tip
    return b.length * math.cos(b.alpha) + lift - _PENETRATION0, lift - _PENETRATION0


def stretches(spec: CrawlerSpec) -> list:
    """The prescribed stretch of each body segment (minus its shortening, mm)."""
    a = spec.actuation
    out = []
    for delay in a.delays(spec.segments):
        start = a.settle_time + delay
        if a.history is None:
            out.append(DelayedSin2(float(a.s_max), float(a.period), float(start), float(a.cycles)))
        else:
            t, s = (np.asarray(v, dtype=float) for v in a.history)
            out.append(SampledStretch(t, s, float(start)))
    return out


def _body_and_bristles(s, spec: CrawlerSpec):
    """Body nodes, masses, actuated links, clamps and bristle chains."""
    c = spec.contact
    drops = [bristle_drop(b, c) for b in spec.bristles]
    y_body = spec.body.link_length + max(d[0] for d in drops)
    body = [s.node(b.position, y_body) for b in spec.bristles]
    m = spec.body.mass / len(body)
    for n in body:
        s.point_mass(n, m)
    for prev, nxt, stretch in zip(body[:-1], body[1:], stretches(spec), strict=True):
        s.rigid_link(nxt, prev, stretch=stretch)
    if not spec.body.free_pitch:
        s.fix(body[0], "theta")
    chains, clamps = [], []
    for node, b in zip(body, spec.bristles, strict=True):
        root, tip = bristle_ends(b, c)
        clamp = s.node(*root)
        s.rigid_link(clamp, node)
        chains.append(tuple(s.chain(clamp, tip, b.elements, b.section())))
        clamps.append(clamp)
    return tuple(body), tuple(clamps), tuple(chains)


def _contact_points(spec: CrawlerSpec, chains):
    """Contact nodes, their offsets and radii (mm), and each tip's points.

    Order: the tips first (their states are the tips' contact states), then the other
    nodes of each bristle; with surface points, all "+n" face points, then all "-n"."""
    c, br = spec.contact, spec.bristles
    n = len(chains)
    nodes = [ch[-1] for ch in chains]
    thick = [float(b.thickness(1.0)) for b in br]
    normals = [b.normal() for b in br]
    if c.nodes == "all":
        for ch, b in zip(chains, br, strict=True):
            nodes += ch[1:-1]
            thick += list(b.node_thickness()[1:-1])
            normals += [b.normal()] * (len(ch) - 2)
    thick, normals = np.asarray(thick), np.asarray(normals)
    if c.surface:
        off = 0.5 * thick[:, None] * normals
        half = len(nodes)
        return (
            nodes + nodes,
            np.concatenate([off, -off]),
            0.0,
            tuple((i, half + i) for i in range(n)),
        )
    radius = 0.5 * thick if c.discs else 0.0
    return nodes, np.zeros((len(nodes), 2)), radius, tuple((i,) for i in range(n))


def _friction_law(spec: CrawlerSpec, weight: float):
    """The scenario's friction law (``contact.friction``) with penalties sized for the
    weight on one bristle, ``weight`` (N; or a given peak load): penetration below 1
    micrometre and stick drift below ``contact.stick_drift`` at that load."""
    c = spec.contact
    load = c.penalty_load or weight
    law = FrictionLaw.of(c.friction)
    options = c.law_options(weight)
    return law.for_reference_load(c.mu, load=load, max_stick_drift=c.stick_drift, **options)


def add_contact(s, spec: CrawlerSpec, chains, weight: float | None = None):
    """Add the contact of ``spec``'s bristle ``chains`` with its substrate to structure
    ``s``: the substrate term (and the corner term where the substrate has convex
    corners); returns (substrate term, corner term or None, each tip's contact points).
    ``weight``: the weight on one bristle of the crawler (N; default ``spec``'s), which
    sizes the penalties and is the power law's default reference load."""
    law = _friction_law(spec, weight_share(spec) if weight is None else weight)
    nodes, offsets, radius, tip_points = _contact_points(spec, chains)
    X = s.coordinates
    term = SubstrateContact(tuple(int(n) for n in nodes), active=spec.contact.active_points)
    s.add_term(
        term,
        SubstrateContact.params(X, term.nodes, spec.substrate, law, radius=radius, offset=offsets),
    )
    corners = None
    # The corner term is contact with the substrate's convex corners: a substrate without
    # any (a flat plane) needs none, whatever the contact settings ask for.
    if spec.contact.corners and spec.substrate.has_corners:
        outlines = [
            beam_outline(ch, b.node_thickness(), b.normal())
            for ch, b in zip(chains, spec.bristles, strict=True)
        ]
        faces = tuple(o[0] for o in outlines)
        period = spec.substrate.period
        span = max(b.length + b.thickness_clamp for b in spec.bristles)
        corners = FaceCornerContact(
            faces, FaceCornerContact.window_periods(span, period, margin=1.0)
        )
        s.add_term(
            corners,
            FaceCornerContact.params(X, faces, [o[1] for o in outlines], spec.substrate, law),
        )
    return term, corners, tip_points


def _drawing(body, clamps, chains):
    lines = [*itertools.pairwise(body)]
    kinds = [LINE_BODY] * len(lines)
    for node, clamp in zip(body, clamps, strict=True):
        lines.append((node, clamp))
        kinds.append(LINE_LINK)
    for ch in chains:
        for pair in itertools.pairwise(ch):
            lines.append(pair)
            kinds.append(LINE_BRISTLE)
    return np.asarray(lines), np.asarray(kinds)


def build(spec: CrawlerSpec) -> CrawlerModel:
    """Check ``spec`` (one-line :class:`InputError`) and build its FE model."""
    spec.check()
    s = fe.Structure()
    body, clamps, chains = _body_and_bristles(s, spec)
    s.gravity(0.0, -spec.gravity)
    # The programs take the a1 K v product only where the damping has one: 9-15 % of a
    # Newton iteration (fe.Structure.stiffness_damping).
    s.stiffness_damping(spec.damping.stiffness_proportional)
    term, corners, tip_points = add_contact(s, spec, chains)
    model = s.build()
    subtrees = tuple(
        tuple(n for j in range(i + 1, len(body)) for n in (body[j], clamps[j], *chains[j][1:]))
        for i in range(len(body) - 1)
    )
    lines, kinds = _drawing(body, clamps, chains)
    return CrawlerModel(
        model=model,
        spec=spec,
        body=body,
        clamps=clamps,
        bristles=chains,
        contact=term,
        corners=corners,
        tip_points=tip_points,
        subtrees=subtrees,
        lines=lines,
        line_kind=kinds,
    )
