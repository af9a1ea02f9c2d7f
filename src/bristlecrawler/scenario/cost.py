"""What a run will cost, estimated before it starts from the measured costs in
``docs/performance.md``; work this machine cannot hold is refused with the estimate.

An FE run takes at least its duration over its largest time step; the paper scenario
(2 bristles of 20 elements, 2,000 such steps) runs 2,429 steps in 20.5-24.3 s of stroke
(``bench/bench_crawler.py``), about 11 ms per step of the bound, taken to grow with the
number of beam elements. Each accepted step keeps one record of every node.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass

from bristlecrawler.errors import InputError
from bristlecrawler.scenario.schema import MAX_STEPS

#: CPU seconds per time step of the lower bound, per beam element (paper: 22.5 s / 2,000
#: steps / 40 elements).
FE_STEP_S_PER_ELEMENT = 22.5 / 2000 / 40
#: A cold start's compilation of a structure's programs, s (63-71 s measured).
FE_COMPILE_S = 70.0
#: Bytes of one step's record per node (position, force, state; rounded up).
RECORD_BYTES_PER_NODE = 200.0
#: Reduced model, CPU seconds per design: the closed form (0.065-0.13 s per 10^6
#: designs) and the exact solver (0.037 s for 2 bristles, 0.24 s for 10 peristaltic).
REDUCED_CLOSED_FORM_S = 1.3e-7
REDUCED_EXACT_S = 0.24
#: Memory of one Dask worker process: 270 MB with JAX and the models imported, doubled
#: for a compiled FE model and its records.
WORKER_BYTES = 0.55e9
#: Bytes a sweep keeps per design while it runs (its task, future and result row).
DESIGN_BYTES = 4e3
#: Work longer than this is announced before it starts, s.
ANNOUNCE_S = 60.0


def machine_memory() -> float:
    """Physical memory of this machine, bytes (8 GB where the system does not say)."""
    try:
        return float(os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES"))
    except (ValueError, OSError, AttributeError):
        return 8e9


@dataclass(frozen=True)
class Estimate:
    """What a piece of work will take: ``steps`` (time steps or designs, as ``unit``
    says), CPU ``seconds`` and ``memory`` (bytes)."""

    what: str
    steps: float
    unit: str
    seconds: float
    memory: float

    def text(self) -> str:
        return (
            f"{self.what}: about {_count(self.steps)} {self.unit}, {duration(self.seconds)} "
            f"of CPU time, {_bytes(self.memory)} of memory"
        )

    def check(self, max_steps: float | None = MAX_STEPS) -> Estimate:
        """InputError, with the estimate, where the machine cannot hold the work."""
        limit = machine_memory()
        if not (self.memory <= 0.8 * limit):
            raise InputError(
                f"{self.text()}: more than this machine's {_bytes(limit)} can hold; "
                "make the work smaller"
            )
        if max_steps is not None and not (self.steps <= max_steps):
            raise InputError(
                f"{self.text()}: more than {max_steps:g} {self.unit}; make the work smaller"
            )
        return self

    @property
    def long(self) -> bool:
        return self.seconds > ANNOUNCE_S


def fe_run(what: str, duration: float, dt_max: float, elements: int, nodes: int) -> Estimate:
    """A run of ``duration`` s with steps of at most ``dt_max`` s over ``elements`` beam
    elements and ``nodes`` nodes."""
    steps = duration / dt_max if dt_max > 0 else math.inf
    seconds = steps * FE_STEP_S_PER_ELEMENT * elements + FE_COMPILE_S
    return Estimate(what, steps, "time steps", seconds, steps * nodes * RECORD_BYTES_PER_NODE)


def fe_crawler(sc) -> Estimate | None:
    """A scenario's run (None for a recorded history, whose length the file sets)."""
    if sc.actuation.kind == "history":
        return None
    b = sc.bristle
    stroke = sc.actuation.cycles * sc.actuation.period + sc.actuation.settle_time
    return fe_run(
        "the run", stroke, sc.solver.dt_max, b.count * b.elements, b.count * (b.elements + 2)
    )


def duration(seconds: float) -> str:
    """``45 s``, ``12 min``, ``3.2 h``, ``1.5e+04 h``."""
    if not math.isfinite(seconds):
        return "an unbounded time"
    if seconds < 120:
        return f"{seconds:.0f} s"
    if seconds < 7200:
        return f"{seconds / 60:.0f} min"
    return f"{seconds / 3600:.3g} h"


def _count(n: float) -> str:
    return f"{n:,.0f}" if n < 1e7 else f"{n:.3g}"


def _bytes(n: float) -> str:
    if not math.isfinite(n):
        return "unbounded"
    for unit, size in (("TB", 1e12), ("GB", 1e9), ("MB", 1e6)):
        if n >= size:
            return f"{n / size:.3g} {unit}"
    return f"{n / 1e3:.3g} kB"
