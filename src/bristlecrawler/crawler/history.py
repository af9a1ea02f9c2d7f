"""What a finite-element crawler run records: time series and deformed-shape frames.

Sign conventions: x to the right (the direction of motion along the grain), y up; the
shortening s is positive when the body is shorter than at rest; the connector force F_c is
the force the actuator exerts on the two ends, positive when it pulls them together; the
connector work is ``W_c = int F_c ds``.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field

import numpy as np

from bristlecrawler.results.run import RunSummary
from bristlecrawler.states import ContactState

TIP_OPEN, TIP_STICK, TIP_SLIP = ContactState.OPEN, ContactState.STICK, ContactState.SLIP

# A bending strain h kappa / 2 above which the beam model certainly does not hold: a
# radius of curvature below the section's own thickness. (A linear-elastic beam is
# already doubtful from about 0.1-0.2.) The paper scenario's sin^2 runs reach 0.08 with
# 20 elements per bristle and 0.17 with 40; a tip element that kinked by 51 degrees on a
# land as wide as the tip (pitch 1.5 mm, 20 elements) reached 1.17.
STRAIN_LIMIT = 0.5

#: A run whose body would still creep more than this fraction of its scale after the
#: gravity step is flagged (:func:`settle_warning`; a crawler's advance per cycle, a drag
#: test's F_p / k): its first cycle or first loading then depends on how the gravity
#: step was stepped.
SETTLE_CREEP_LIMIT = 0.01


def settle_warning(stats: dict, scale: float, what: str, against: str, effect: str) -> str | None:
    """The warning of a run whose ``what`` (the body, the carriage) still moved at the end
    of the gravity step by enough to matter: the distance it would still creep there
    (``stats["settle_creep_mm"]``) above :data:`SETTLE_CREEP_LIMIT` times ``scale`` (mm),
    which ``against`` names; ``effect`` says what depends on it (None: settled, not
    recorded, or no finite scale)."""
    creep = stats.get("settle_creep_mm")
    if creep is None or not np.isfinite(scale) or not creep > SETTLE_CREEP_LIMIT * abs(scale):
        return None
    speed = stats.get("settle_speed_mm_s", float("nan"))
    return (
        f"the {what} still moved at {speed:.3g} mm/s at the end of the gravity step (about "
        f"{creep:.2g} mm more to go, against {against}): {effect}; lengthen "
        "actuation.settle_time"
    )


@dataclass(frozen=True)
class StrainPeak:
    """The largest bending strain over a run's recorded steps (every accepted step, more
    than the frames a run folder keeps), from the turn of a bristle's axis between
    adjacent elements: strain = |dtheta| h / (2 l), l the two elements' mean length, h
    the section thickness at their shared node. With shear-deformable beams the chords'
    turn also holds the change of shear angle; the clamp node is not checked. bristle:
    its index from the left; node: index along the bristle from its clamp; t: s from the start of
    the stroke (0 is the end of the gravity step); first_over: the first such time at
    which any bristle's strain exceeded :data:`STRAIN_LIMIT` (None if none did)."""

    strain: float
    turn_deg: float
    bristle: int
    node: int
    t: float
    first_over: float | None = None

    def message(self) -> str:
        text = (
            f"bristle {self.bristle} (from the left) turns by {self.turn_deg:.1f} deg at "
            f"its node {self.node} (from the clamp) at t = {self.t:.3g} s: a bending "
            f"strain of {self.strain:.2f}"
        )
        if self.first_over is None:
            return text
        since = (
            "the end of the gravity step"
            if self.first_over <= 0.0
            else (f"t = {self.first_over:.3g} s")
        )
        return (
            f"{text}; strains above {STRAIN_LIMIT:g} (a radius of curvature below the "
            f"section's thickness: outside the beam model) from {since} on, so the run is "
            "not to be trusted from there (refine bristle.elements)"
        )


@dataclass(frozen=True)
class CrawlerHistory:
    """Time series (index m) and frames (index f) of a run.

    Attributes:
        t: times, s, (M,), from the start of the stroke. s: shortening, mm, (M,).
        left, right: positions (x, y) of the body's first and last node, mm, (M, 2).
        connector_force: F_c, N, (M,). connector_work: W_c, mJ, (M,).
        tip_position: (x, y) of each bristle tip, mm, (M, B, 2).
        tip_state: 0 open, 1 stick, 2 slip, (M, B).
        energies: name -> (M,) series in mJ (elastic, kinetic, potential, friction,
            damping, external, ...).
        frame_t: frame times, s, (F,). frame_nodes: node positions, mm, (F, P, 2).
        lines: line-cell connectivity of the drawing, (C, 2).
        line_kind: 0 body/connector, 1 rigid link, 2 bristle element, (C,).
        substrate_xy: one drawing of the substrate surface, mm, (K, 2).
        period: stroke period T, s (None for a recorded history).
        node_thickness: section thickness at each node, mm, (P,) (0 off the bristles;
            None: not recorded), for drawing the bristles' outlines.
        cycles: number of cycles.
        stats: counters of the solve (steps, iterations, wall time, ...).
        segment_shortening: shortening of each body segment, mm, (M, S) (S = bristles - 1;
            ``s`` is the first segment's).
        segment_force: connector force of each segment's actuator, N, (M, S)
            (``connector_force`` is the first segment's; ``connector_work`` is the work of
            all of them).
        name: the design's name.
        quantities: the declared quantities (:mod:`.quantities`) that have no attribute of
            their own, by name.

    The unit, dimensions and meaning of each recorded series are declared once, in
    :data:`bristlecrawler.crawler.quantities.QUANTITIES`.
    """

    t: np.ndarray
    s: np.ndarray
    left: np.ndarray
    right: np.ndarray
    connector_force: np.ndarray
    connector_work: np.ndarray
    tip_position: np.ndarray
    tip_state: np.ndarray
    energies: dict[str, np.ndarray]
    frame_t: np.ndarray
    frame_nodes: np.ndarray
    lines: np.ndarray
    line_kind: np.ndarray
    substrate_xy: np.ndarray
    period: float | None = None
    cycles: int = 1
    stats: dict = field(default_factory=dict)
    node_thickness: np.ndarray | None = None
    segment_shortening: np.ndarray | None = None
    segment_force: np.ndarray | None = None
    name: str = "custom"
    quantities: dict[str, np.ndarray] = field(default_factory=dict)

    @property
    def delta(self) -> np.ndarray:
        """Displacement of the right end, mm (the paper's Delta)."""
        return self.right[:, 0] - self.right[0, 0]

    @property
    def net_advance(self) -> float:
        return float(self.delta[-1])

    def cycle_bounds(self) -> np.ndarray:
        """Indices of the samples closest to t = n T (n = 0..cycles), relative to t[0]."""
        if self.period is None:
            return np.array([0, self.t.size - 1])
        marks = self.t[0] + np.arange(self.cycles + 1) * self.period
        return np.clip(np.searchsorted(self.t, marks - 1e-9 * self.period), 0, self.t.size - 1)

    def advance_per_cycle(self) -> np.ndarray:
        b = self.cycle_bounds()
        return np.diff(self.delta[b])

    def bristle_chains(self) -> list[np.ndarray]:
        """Node indices of each bristle (a chain of bristle line cells), clamp to tip,
        ordered left to right."""
        segs = self.lines[self.line_kind == 2]
        nbrs: dict[int, list[int]] = {}
        for a, b in segs:
            nbrs.setdefault(int(a), []).append(int(b))
            nbrs.setdefault(int(b), []).append(int(a))
        y0 = self.frame_nodes[0, :, 1]
        chains, seen = [], set()
        # Each chain from its higher end (the clamp) along its neighbours.
        for end in sorted((n for n, nb in nbrs.items() if len(nb) == 1), key=lambda n: -y0[n]):
            if end in seen:
                continue
            chain, prev = [end], None
            while True:
                nxt = [n for n in nbrs[chain[-1]] if n != prev]
                if not nxt:
                    break
                prev = chain[-1]
                chain.append(nxt[0])
            seen.update(chain)
            chains.append(np.array(chain))
        return sorted(chains, key=lambda ix: self.frame_nodes[0, ix, 0].min())

    def strain_peak(self) -> StrainPeak | None:
        """The largest bending strain over all frames (:class:`StrainPeak`), or None
        without the section thicknesses or a bristle of three nodes."""
        if self.node_thickness is None:
            return None
        best, first = None, None
        for k, chain in enumerate(self.bristle_chains()):
            if chain.size < 3:
                continue
            d = np.diff(self.frame_nodes[:, chain], axis=1)  # (F, n - 1, 2)
            turn = np.abs(np.diff(np.unwrap(np.arctan2(d[..., 1], d[..., 0]), axis=1), axis=1))
            length = np.linalg.norm(d, axis=2)
            mean = 0.5 * (length[:, 1:] + length[:, :-1])
            strain = turn * self.node_thickness[chain][1:-1] / (2.0 * mean)
            over = np.flatnonzero(np.any(strain > STRAIN_LIMIT, axis=1))
            if over.size and (first is None or self.frame_t[over[0]] < first):
                first = float(self.frame_t[over[0]])
            f, j = np.unravel_index(np.argmax(strain), strain.shape)
            if best is None or strain[f, j] > best.strain:
                t = float(self.frame_t[f])
                turn_deg = float(np.degrees(turn[f, j]))
                best = StrainPeak(float(strain[f, j]), turn_deg, k, int(j) + 1, t)
        return None if best is None else dataclasses.replace(best, first_over=first)

    def to_dataset(self, attrs: dict | None = None):
        """The run as an xarray Dataset (see :mod:`bristlecrawler.crawler.dataset`)."""
        from bristlecrawler.crawler.dataset import crawler_dataset

        return crawler_dataset(self, attrs)

    def summary(self) -> RunSummary:
        """Summary numbers of the run (:class:`~bristlecrawler.results.RunSummary`;
        ``.to_dict()`` is the CLI's summary.json); the advance and the work are the run's
        :class:`RunMetrics`."""
        from bristlecrawler.crawler.metrics import run_metrics

        work = self.connector_work
        b = self.cycle_bounds()
        st = self.stats
        peak = self.strain_peak()
        warnings = []
        if peak is not None and peak.strain > STRAIN_LIMIT:
            warnings.append(peak.message())
        unsettled = self.unsettled()
        if unsettled is not None:
            warnings.append(unsettled)
        nan = float("nan")
        force = self.connector_force if self.segment_force is None else self.segment_force
        span = max(self.t[-1] - self.t[0], 1e-300)
        return RunSummary(
            scenario=self.name,
            bristles=int(self.tip_position.shape[1]),
            metrics=run_metrics(self),
            work_per_cycle=tuple(np.diff(work[b]).tolist()),
            mean_abs_connector_force=float(
                np.trapezoid(np.abs(self.connector_force), self.t) / span
            ),
            max_abs_connector_force=float(np.max(np.abs(force))),
            energy_balance_rel_error=self.energy_balance_rel_error(),
            friction_dissipation=float(self.energies.get("friction", [0.0])[-1]),
            damping_dissipation=float(self.energies.get("damping", [0.0])[-1]),
            wall_time=float(st.get("wall_time_s", nan)),
            compile_time=float(st.get("compile_time_s", nan)),
            stroke_wall_time=float(st.get("stroke_wall_time_s", nan)),
            steps=int(st.get("steps", self.t.size - 1)),
            newton_iterations=int(st.get("newton_iterations", 0)),
            rejected_steps=int(st.get("rejected_steps", 0)),
            first_frequency=float(st.get("first_frequency_hz", nan)),
            rayleigh_a0=float(st.get("rayleigh_a0", nan)),
            max_bristle_strain=nan if peak is None else peak.strain,
            settle_speed=float(st.get("settle_speed_mm_s", nan)),
            settle_creep=float(st.get("settle_creep_mm", nan)),
            warnings=tuple(warnings),
        )

    def unsettled(self) -> str | None:
        """A warning when the body still moved at the end of the gravity step by enough
        to matter: the distance it would still creep there (``settle_creep_mm``) above
        :data:`SETTLE_CREEP_LIMIT` times the largest advance of a cycle (None: settled,
        or not recorded)."""
        advance = np.abs(self.advance_per_cycle())
        scale = float(np.max(advance)) if advance.size else 0.0
        return settle_warning(
            self.stats,
            scale,
            "body",
            f"{scale:.3g} mm of advance per cycle",
            "the first cycle starts from a state that depends on the gravity step's time steps",
        )

    def energy_balance_residual(self) -> np.ndarray:
        """external - (elastic + kinetic + potential + friction + damping), mJ."""
        e = self.energies
        stored = sum(e.get(k, 0.0) for k in ("elastic", "kinetic", "potential"))
        lost = sum(e.get(k, 0.0) for k in ("friction", "damping"))
        return e["external"] - stored - lost

    def energy_balance_rel_error(self) -> float:
        r = self.energy_balance_residual()
        scale = max(float(np.max(np.abs(self.energies["external"]))), 1e-300)
        return float(np.max(np.abs(r - r[0])) / scale)
