"""The drag test's options at the edge: bounds per quantity, and the test's cost."""

from __future__ import annotations

from typing import Literal

from pydantic import Field

from bristlecrawler.scenario.cost import Estimate, fe_run
from bristlecrawler.scenario.schema import MAX_LENGTH
from bristlecrawler.scenario.strict import StrictSection


class DragOptions(StrictSection):
    """What ``bristlecrawler drag`` does (see :class:`bristlecrawler.crawler.DragTest`)."""

    direction: Literal["along", "against", "cycle"] = Field(
        "cycle", description="along (+x), against (-x) or cycle (both, back and forth)"
    )
    distance: float = Field(
        20.0, gt=0, le=MAX_LENGTH, allow_inf_nan=False, description="travel of each leg, mm"
    )
    speed: float = Field(
        2.0,
        ge=1e-4,
        le=1e3,
        allow_inf_nan=False,
        description="carriage speed, mm/s; quasi-static is far below the bound",
    )
    legs: int = Field(2, ge=2, le=10_000, description="legs of a cycle")
    load: float | None = Field(
        None,
        gt=0,
        le=1e4,
        allow_inf_nan=False,
        description="vertical load on the bristle, N; 1e4 N is a tonne's weight",
    )

    def test(self):
        from bristlecrawler.crawler.drag import DragTest

        return DragTest(self.direction, self.distance, self.speed, self.legs, 0, self.load)


def drag_estimate(sc, test) -> Estimate:
    """The drag test's steps (of at most ``resolution`` mm of travel and of solver.dt_max),
    CPU time and memory, for one bristle of scenario ``sc``."""
    dt = min(sc.solver.dt_max, test.resolution / test.speed)
    settle = sc.actuation.settle_time
    elements = sc.bristle.elements
    return fe_run("the drag test", test.duration + settle, dt, elements, elements + 2)
