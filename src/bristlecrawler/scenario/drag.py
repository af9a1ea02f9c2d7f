"""The drag test's options at the edge, generated from :class:`~bristlecrawler.crawler.DragTest`'s
declared settings, and the test's cost."""

from __future__ import annotations

from bristlecrawler.crawler.drag import DragTest
from bristlecrawler.scenario.cost import Estimate, fe_run
from bristlecrawler.scenario.strict import StrictSection, section_of


class _DragTable(StrictSection):
    """The options of ``bristlecrawler drag`` (see :class:`DragTest`)."""

    def test(self) -> DragTest:
        """The drag test these options describe (on the design's first bristle)."""
        return DragTest(**self.model_dump())


def _no_rules(table) -> None:
    """The drag test's rules need the design (a leg of at least one pitch, a bristle it
    has): :meth:`DragTest.check` runs them once the scenario is read."""


#: What ``bristlecrawler drag`` does: :class:`DragTest`'s settings but which bristle and
#: the step's resolution (the command drags the first bristle at the default resolution).
DragOptions = section_of(
    DragTest,
    _DragTable,
    "What ``bristlecrawler drag`` does (see :class:`bristlecrawler.crawler.DragTest`).",
    exclude=("bristle", "resolution"),
    rules=_no_rules,
    name="DragOptions",
)


def drag_estimate(sc, test) -> Estimate:
    """The drag test's steps (of at most ``resolution`` mm of travel and of solver.dt_max),
    CPU time and memory, for one bristle of scenario ``sc``."""
    dt = min(sc.solver.dt_max, test.resolution / test.speed)
    settle = sc.actuation.settle_time
    elements = sc.bristle.elements
    return fe_run("the drag test", test.duration + settle, dt, elements, elements + 2)
