"""What a finite-element crawler run records: time series and deformed-shape frames.

Sign conventions: x to the right (the direction of motion along the grain), y up; the
shortening s is positive when the body is shorter than at rest; the connector force F_c is
the force the actuator exerts on the two ends, positive when it pulls them together; the
connector work is ``W_c = int F_c ds``.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

TIP_OPEN, TIP_STICK, TIP_SLIP = 0, 1, 2


@dataclass(frozen=True)
class CrawlerHistory:
    """Time series (index m) and frames (index f) of a run.

    Attributes:
        t: times, s, (M,). s: shortening, mm, (M,).
        left, right: positions (x, y) of the body's left and right ends, mm, (M, 2).
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
