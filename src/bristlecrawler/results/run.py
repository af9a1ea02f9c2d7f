"""What one FE crawler run gives, typed: :class:`RunSummary` (its ``to_dict`` is the run's
``summary.json``)."""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Any

from bristlecrawler.results import keys
from bristlecrawler.results.metrics import RunMetrics


@dataclass(frozen=True)
class RunSummary:
    """The summary numbers of an FE crawler run (NaN where the run did not record one).

    Attributes:
        scenario: the design's name.
        bristles: number of bristles.
        metrics: net advance, advance of each cycle (mm) and actuator work (mJ).
        work_per_cycle: actuator work of each cycle, mJ.
        mean_abs_connector_force: time mean of the actuator force |F_c|, N.
        max_abs_connector_force: largest actuator (or segment) force |F_c|, N.
        energy_balance_rel_error: energy-balance residual relative to the work.
        friction_dissipation, damping_dissipation: energy dissipated over the run, mJ.
        wall_time, compile_time, stroke_wall_time: wall time of the run, of its compiles
            and of its stroke, s.
        steps, newton_iterations, rejected_steps: counters of the solve.
        first_frequency: first resonance of the settled crawler, Hz.
        rayleigh_a0: the mass-proportional damping coefficient, 1/s.
        max_bristle_strain: largest bristle strain of the run, -.
        settle_speed: the body's speed at the end of the gravity step, mm/s.
        settle_creep: how far it would still creep there, mm.
        warnings: one line each, on what makes the numbers doubtful.
    """

    scenario: str
    bristles: int
    metrics: RunMetrics
    work_per_cycle: tuple[float, ...]
    mean_abs_connector_force: float
    max_abs_connector_force: float
    energy_balance_rel_error: float
    friction_dissipation: float
    damping_dissipation: float
    wall_time: float
    compile_time: float
    stroke_wall_time: float
    steps: int
    newton_iterations: int
    rejected_steps: int
    first_frequency: float
    rayleigh_a0: float
    max_bristle_strain: float
    settle_speed: float
    settle_creep: float
    warnings: tuple[str, ...] = ()

    def with_warnings(self, more) -> RunSummary:
        """The summary with the warnings ``more`` (lines) added after its own."""
        return dataclasses.replace(self, warnings=self.warnings + tuple(more))

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready values, units in the keys (the run's ``summary.json``)."""
        return {
            "scenario": self.scenario,
            "bristles": self.bristles,
            **self.metrics.to_dict(),
            keys.WORK_PER_CYCLE_MJ: list(self.work_per_cycle),
            keys.MEAN_ABS_CONNECTOR_FORCE_N: self.mean_abs_connector_force,
            keys.MAX_ABS_CONNECTOR_FORCE_N: self.max_abs_connector_force,
            keys.ENERGY_BALANCE_REL_ERROR: self.energy_balance_rel_error,
            "friction_dissipation_mJ": self.friction_dissipation,
            "damping_dissipation_mJ": self.damping_dissipation,
            keys.WALL_TIME_S: self.wall_time,
            "compile_time_s": self.compile_time,
            "stroke_wall_time_s": self.stroke_wall_time,
            keys.STEPS: self.steps,
            keys.NEWTON_ITERATIONS: self.newton_iterations,
            "rejected_steps": self.rejected_steps,
            "first_frequency_hz": self.first_frequency,
            "rayleigh_a0_per_s": self.rayleigh_a0,
            "max_bristle_strain": self.max_bristle_strain,
            keys.SETTLE_SPEED_MM_S: self.settle_speed,
            keys.SETTLE_CREEP_MM: self.settle_creep,
            "warnings": list(self.warnings),
        }
