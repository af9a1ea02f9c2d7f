"""What a crawler run gives, as typed results, whatever the model (reduced, FE, closed form).

The results layer: the FE crawler, the reduced models, the studies and the jobs all
import it, and it imports none of them.

* :class:`RunMetrics`: the motion of one run and its cost (net advance, advance of each
  cycle, actuator work), what the reduced job, the prediction and the report print.
* :class:`DesignMetrics`: the outputs a design study records for each design.

Fields carry no unit in their names; their docs say the unit, and ``to_dict`` gives the
JSON key names, units in the keys, that the output files have always used.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from bristlecrawler.results.keys import (
    ADVANCE_PER_CYCLE_MM,
    COST_OF_TRANSPORT,
    ENERGY_BALANCE_REL_ERROR,
    LAST_CYCLE_ADVANCE_MM,
    MAX_ABS_CONNECTOR_FORCE_N,
    MEAN_ABS_CONNECTOR_FORCE_N,
    NET_ADVANCE_MM,
    NEWTON_ITERATIONS,
    STEPS,
    WALL_TIME_S,
    WORK_MJ,
)


@dataclass(frozen=True)
class RunMetrics:
    """The motion of a crawler run and its cost.

    Attributes:
        net_advance: displacement of the front end at the end of the run, mm.
        advance_per_cycle: the front end's advance over each whole cycle, mm.
        work: actuator (connector) work over the run, mJ.
    """

    net_advance: float
    advance_per_cycle: tuple[float, ...]
    work: float

    @classmethod
    def from_reduced(cls, result) -> RunMetrics:
        """The metrics of a reduced-model run (:class:`~bristlecrawler.reduced.ReducedResult`)."""
        advance, _ = result.per_cycle()
        return cls(result.net_advance, tuple(advance.tolist()), float(result.work[-1]))

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready values, units in the keys."""
        return {
            NET_ADVANCE_MM: self.net_advance,
            ADVANCE_PER_CYCLE_MM: list(self.advance_per_cycle),
            WORK_MJ: self.work,
        }

    @classmethod
    def from_dict(cls, data: dict[str, Any]) -> RunMetrics:
        """The metrics back from :meth:`to_dict`'s keys (other keys are ignored); a null
        (how a JSON file writes NaN) reads as NaN."""
        return cls(
            _number(data[NET_ADVANCE_MM]),
            tuple(_number(a) for a in data[ADVANCE_PER_CYCLE_MM]),
            _number(data[WORK_MJ]),
        )


def _number(value) -> float:
    return math.nan if value is None else float(value)


#: DesignMetrics field -> (JSON key, unit, description), in the order of the outputs.
_DESIGN_OUTPUTS: dict[str, tuple[str, str, str]] = {
    "net_advance": (NET_ADVANCE_MM, "mm", "displacement of the front end at the end of the run"),
    "advance_per_cycle": (
        ADVANCE_PER_CYCLE_MM,
        "mm",
        "net advance divided by the number of cycles",
    ),
    "last_cycle_advance": (
        LAST_CYCLE_ADVANCE_MM,
        "mm",
        "advance of the last cycle (the steady gait)",
    ),
    "work": (WORK_MJ, "mJ", "actuator (connector) work over the run"),
    "cost_of_transport": (
        COST_OF_TRANSPORT,
        "mJ/mm",
        "work per mm of net advance (NaN where the crawler does not advance)",
    ),
    "mean_abs_connector_force": (
        MEAN_ABS_CONNECTOR_FORCE_N,
        "N",
        "time mean of the actuator force |F_c|",
    ),
    "max_abs_connector_force": (MAX_ABS_CONNECTOR_FORCE_N, "N", "largest actuator force |F_c|"),
    "energy_balance_rel_error": (
        ENERGY_BALANCE_REL_ERROR,
        "1",
        "energy-balance residual relative to the work",
    ),
    "steps": (STEPS, "1", "time steps (fe) or samples (reduced exact solver; 0: closed form)"),
    "newton_iterations": (
        NEWTON_ITERATIONS,
        "1",
        "Newton iterations (fe; 0 for the reduced model)",
    ),
    "wall_time": (WALL_TIME_S, "s", "wall time of the design on its worker"),
}

#: JSON key -> (unit, description) of every output of a design, any model.
DESIGN_OUTPUTS: dict[str, tuple[str, str]] = {
    key: (unit, text) for key, unit, text in _DESIGN_OUTPUTS.values()
}


@dataclass(frozen=True)
class DesignMetrics:
    """The outputs of one design of a study (floats), or of a chunk of designs (arrays
    over the designs, as the closed forms give them).

    Attributes:
        net_advance: displacement of the front end at the end of the run, mm.
        last_cycle_advance: advance of the last cycle (the steady gait), mm; NaN without
            a whole cycle.
        cycles: number of cycles run.
        work: actuator (connector) work over the run, mJ.
        mean_abs_connector_force: time mean of the actuator force |F_c|, N.
        max_abs_connector_force: largest actuator force |F_c|, N.
        energy_balance_rel_error: energy-balance residual relative to the work.
        steps: time steps (FE), samples (reduced exact solver) or 0 (closed form).
        newton_iterations: Newton iterations (FE; 0 for the reduced model).
        wall_time: wall time of the design, s; None where the worker measures it.
    """

    net_advance: Any
    last_cycle_advance: Any
    cycles: Any
    work: Any
    mean_abs_connector_force: Any
    max_abs_connector_force: Any
    energy_balance_rel_error: Any
    steps: Any
    newton_iterations: Any
    wall_time: Any = None

    @property
    def advance_per_cycle(self):
        """Net advance divided by the number of cycles, mm."""
        return np.asarray(self.net_advance, float) / np.asarray(self.cycles, float)

    @property
    def cost_of_transport(self):
        """Work per mm of net advance, mJ/mm (NaN where the crawler does not advance)."""
        adv = np.asarray(self.net_advance, float)
        work = np.asarray(self.work, float)
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.where(adv > 0, work / adv, np.nan)

    @classmethod
    def from_reduced(cls, result, cycles: int) -> DesignMetrics:
        """The outputs of a reduced-model run (:class:`~bristlecrawler.reduced.ReducedResult`)
        of ``cycles`` cycles."""
        run = RunMetrics.from_reduced(result)
        # The actuator of segment j carries the bristle forces on its left: F_c = -sum_{i<=j} F_i.
        fc = np.abs(np.cumsum(result.force, axis=1)[:, :-1])
        span = max(float(result.t[-1] - result.t[0]), 1e-300)
        return cls(
            net_advance=run.net_advance,
            last_cycle_advance=run.advance_per_cycle[-1] if run.advance_per_cycle else math.nan,
            cycles=cycles,
            work=run.work,
            mean_abs_connector_force=float(np.trapezoid(fc.mean(axis=1), result.t) / span),
            max_abs_connector_force=float(fc.max()),
            energy_balance_rel_error=result.energy_balance_error,
            steps=int(result.t.size),
            newton_iterations=0,
        )

    @classmethod
    def from_summary(cls, summary: dict[str, Any], cycles: int) -> DesignMetrics:
        """The outputs of a run's summary (an FE crawler history's ``summary()``: its
        advance of each cycle, connector force, solver counters and wall time)."""
        run = RunMetrics.from_dict(summary)

        def get(field: str, default: Any = math.nan) -> Any:
            return summary.get(_DESIGN_OUTPUTS[field][0], default)

        last = run.advance_per_cycle[-1] if run.advance_per_cycle else math.nan
        return cls(
            net_advance=run.net_advance,
            last_cycle_advance=last,
            cycles=cycles,
            work=run.work,
            mean_abs_connector_force=get("mean_abs_connector_force"),
            max_abs_connector_force=get("max_abs_connector_force"),
            energy_balance_rel_error=get("energy_balance_rel_error"),
            steps=get(STEPS),
            newton_iterations=get("newton_iterations"),
            wall_time=get("wall_time", None),
        )

    def to_dict(self) -> dict[str, Any]:
        """The outputs under their JSON keys (units in the keys), in :data:`DESIGN_OUTPUTS`
        order; without ``wall_time_s`` while it is None."""
        return {
            key: getattr(self, field)
            for field, (key, _, _) in _DESIGN_OUTPUTS.items()
            if not (field == "wall_time" and self.wall_time is None)
        }
