"""``bristlecrawler reproduce``: the whole paper in one run, as a report.

The report is a tuple of parts (:class:`Part`: a name, ``run(ctx) -> PartResult``, a
title); :data:`PARTS` holds the paper's, in order. Public API: :func:`run_reproduce`,
:class:`ReproduceOptions`, :class:`ReproduceRun`, :class:`Settings`.
"""

from bristlecrawler.jobs.reproduce.parts import Context, Figure, Part, PartResult, Settings
from bristlecrawler.jobs.reproduce.run import (
    PARTS,
    ReproduceOptions,
    ReproduceRun,
    run_reproduce,
)
from bristlecrawler.jobs.reproduce.table import ROWS, Row

__all__ = [
    "PARTS",
    "ROWS",
    "Context",
    "Figure",
    "Part",
    "PartResult",
    "ReproduceOptions",
    "ReproduceRun",
    "Row",
    "Settings",
    "run_reproduce",
]
