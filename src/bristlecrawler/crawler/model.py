"""Assembly of the finite-element bristle crawler from a :class:`Scenario` (paper Sec. 3).

Geometry (x right, y up, mm): the left end of the body is the master node (a rigid body that
can translate and pitch); the right end is a slave at the body length L - s(t) (the
actuator); rigid vertical links of ``link_length`` go down from both ends to the clamps; each
bristle is a chain of tapered corotational beam elements from its clamp, inclined by alpha
from the vertical with the tip trailing (to the left for alpha > 0), so the tip starts on
the substrate's top level y = 0. Point masses of ``end_mass`` sit at both ends; bristle
masses come from their density. Tips (or all bristle nodes) are in frictional contact with
the rigid substrate.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

import numpy as np

from bristlecrawler.errors import InputError
from bristlecrawler.scenario.schema import Scenario


@dataclass(frozen=True)
class CrawlerModel:
    """The built model and the node bookkeeping a run needs."""

    model: object  # bristlecrawler.fe.Model
    scenario: Scenario
    left: int
    right: int
    clamps: tuple[int, int]
    bristles: tuple[tuple[int, ...], tuple[int, ...]]
    contact_nodes: tuple[int, ...]
    contact_term_index: int
    tip_points: tuple[tuple[int, ...], tuple[int, ...]]
    right_subtree: tuple[int, ...]
    lines: np.ndarray
    line_kind: np.ndarray
    t_start: float

    @property
    def tips(self) -> tuple[int, int]:
        return self.bristles[0][-1], self.bristles[1][-1]


def _stretch(sc: Scenario):
    from bristlecrawler.crawler.actuation import DelayedSin2, SampledStretch

    a = sc.actuation
    delay = a.settle_time
    if a.kind == "sin2":
        return DelayedSin2(float(a.s_max), float(a.period), float(delay), float(a.cycles))
    if a.kind == "history":
        from bristlecrawler.reduced.strokes import read_history_csv

        st = read_history_csv(a.history)
    else:
        from bristlecrawler.experiment.sma import SMAActuator, run_sma

        st = run_sma(SMAActuator(s_target=a.s_max), a.cycles).stroke()
    if st.s_max >= sc.body.length:
        raise InputError(f"history: shortening {st.s_max:g} mm reaches the body length")
    return SampledStretch(np.asarray(st.t - st.t[0]), np.asarray(st.s), float(delay))


def stroke_duration(sc: Scenario) -> float:
    """Duration of step 2, s."""
    a = sc.actuation
    if a.kind == "sin2":
        return a.cycles * a.period
    st = _stretch(sc)
    return float(st.t[-1])


def build_crawler(
    sc: Scenario,
    contact: str | None = None,
    penalty_load: float | None = None,
    surface: bool | None = None,
    corners: bool | None = None,
):
    """Build the FE model of scenario ``sc``.

    ``contact`` ("tip" or "all" bristle nodes), ``surface`` (contact points on both faces
    of the beam rather than on its axis) and ``penalty_load`` (N) override the scenario's
    ``[contact]`` table.
    """
    from bristlecrawler import fe
    from bristlecrawler.contact.coulomb import CoulombLaw
    from bristlecrawler.contact.term import SubstrateContact

    b, br = sc.body, sc.bristle
    contact = sc.contact.nodes if contact is None else contact
    surface = sc.contact.surface if surface is None else surface
    corners = sc.contact.corners if corners is None else corners
    penalty_load = sc.contact.penalty_load if penalty_load is None else penalty_load
    alpha = math.radians(br.alpha_deg)
    pen = 1e-3
    discs = sc.contact.discs and not surface
    # With surface contact the tip's lower face corner touches the surface, not its axis;
    # a disc touches it with its rim.
    lift = 0.5 * br.thickness_tip * abs(math.sin(alpha)) if surface else 0.0
    if discs:
        lift = 0.5 * br.thickness_tip
    drop = br.length * math.cos(alpha) + lift - pen
    y_end = b.link_length + drop
    s = fe.Structure()
    left = s.node(0.0, y_end)
    right = s.node(b.length, y_end)
    s.point_mass(left, b.end_mass)
    s.point_mass(right, b.end_mass)
    s.rigid_link(right, left, stretch=_stretch(sc))
    if not b.free_pitch:
        s.fix(left, "theta")
    section = fe.TaperedRect(
        E=br.youngs_modulus,
        b=br.width,
        h0=br.thickness_clamp,
        h1=br.thickness_tip,
        rho=br.density,
        nu=br.poisson_ratio,
        shear=br.shear,
    )
    chains, clamps = [], []
    for end in (left, right):
        x0 = b.length if end == right else 0.0
        clamp = s.node(x0, drop)
        s.rigid_link(clamp, end)
        tip = (x0 - br.length * math.sin(alpha), lift - pen)
        chains.append(tuple(s.chain(clamp, tip, br.elements, section)))
        clamps.append(clamp)
    s.gravity(0.0, -sc.gravity)
    # The programs take the a1 K v product only where the damping has one: 9-15 % of a
    # Newton iteration in paired runs (fe.Structure.stiffness_damping).
    d = sc.damping
    s.stiffness_damping(d.kind == "stiffness" or (d.kind == "explicit" and d.a1 != 0.0))
    n_el = br.elements
    if contact == "tip":
        cnodes = [chains[0][-1], chains[1][-1]]
        frac = np.ones(2)
    elif contact == "all":
        # Tips first (their states are the tips' contact states), then the other nodes.
        cnodes = [chains[0][-1], chains[1][-1], *chains[0][1:-1], *chains[1][1:-1]]
        inner = np.arange(1, n_el) / n_el
        frac = np.concatenate([[1.0, 1.0], inner, inner])
    else:
        raise InputError(f"contact must be 'tip' or 'all', got {contact!r}")
    if surface:
        # Points on both faces of the beam, h/2 from the axis along the section's normal;
        # they turn with the node's rotation. Order: tips' "+n" points, the rest's "+n"
        # points, then all "-n" points (so the first two are the tips).
        thickness = br.thickness_clamp + (br.thickness_tip - br.thickness_clamp) * frac
        normal = np.array([math.cos(alpha), -math.sin(alpha)])
        off = 0.5 * thickness[:, None] * normal[None, :]
        offsets = np.concatenate([off, -off])
        half = len(cnodes)
        cnodes = cnodes + cnodes
        tip_points = ((0, half), (1, half + 1))
    else:
        offsets = np.zeros((len(cnodes), 2))
        tip_points = ((0,), (1,))
    radius = 0.0
    if discs:
        radius = 0.5 * (br.thickness_clamp + (br.thickness_tip - br.thickness_clamp) * frac)
    # Penalties sized for the weight on one bristle (or a given peak load): penetration
    # below 1 micrometre and stick drift below contact.stick_drift at that load.
    weight = (
        2 * b.end_mass
        + 2 * br.density * br.width * br.length * 0.5 * (br.thickness_clamp + br.thickness_tip)
    ) * sc.gravity
    law = CoulombLaw.for_reference_load(
        sc.substrate.mu, load=penalty_load or weight / 2, max_stick_drift=sc.contact.stick_drift
    )
    X = np.asarray(s._X)  # reference coordinates (builder internal, read-only use)
    term = SubstrateContact(tuple(int(n) for n in cnodes), active=sc.contact.active_points)
    s.add_term(
        term,
        SubstrateContact.params(
            X, term.nodes, sc.substrate.build(), law, radius=radius, offset=offsets
        ),
    )
    if corners:
        from bristlecrawler.contact.corner import FaceCornerContact, beam_outline

        # The closed outline of each bristle (both faces, tip end, clamp section).
        frac_all = np.arange(n_el + 1) / n_el
        thick = br.thickness_clamp + (br.thickness_tip - br.thickness_clamp) * frac_all
        normal = np.array([math.cos(alpha), -math.sin(alpha)])
        outlines = [beam_outline(ch, thick, normal) for ch in chains]
        faces = tuple(o[0] for o in outlines)
        sub = sc.substrate.build()
        period = float(sub.profile().period)
        span = br.length + br.thickness_clamp
        cterm = FaceCornerContact(faces, FaceCornerContact.window_periods(span, period, margin=1.0))
        s.add_term(cterm, FaceCornerContact.params(X, faces, [o[1] for o in outlines], sub, law))
    model = s.build()
    lines = [(left, right), (left, clamps[0]), (right, clamps[1])]
    kinds = [0, 1, 1]
    for ch in chains:
        for a_, b_ in itertools.pairwise(ch):
            lines.append((a_, b_))
            kinds.append(2)
    subtree = (right, clamps[1], *chains[1][1:])
    return CrawlerModel(
        model=model,
        scenario=sc,
        left=left,
        right=right,
        clamps=tuple(clamps),
        bristles=tuple(chains),
        contact_nodes=term.nodes,
        contact_term_index=0,
        tip_points=tip_points,
        right_subtree=subtree,
        lines=np.asarray(lines),
        line_kind=np.asarray(kinds),
        t_start=0.0,
    )
