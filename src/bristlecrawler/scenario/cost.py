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

#: CPU seconds of the paper run's stroke (five cycles; for an FE design whose length a
#: history file sets).
FE_PAPER_RUN_S = 22.5
#: CPU seconds per time step of the lower bound, per beam element (paper: 2,000 steps of
#: 2 x 20 elements).
FE_STEP_S_PER_ELEMENT = FE_PAPER_RUN_S / 2000 / 40
#: A cold start's compilation of a structure's programs, s (63-71 s measured).
FE_COMPILE_S = 70.0
#: Bytes of one step's record per node (position, force, state; rounded up).
RECORD_BYTES_PER_NODE = 200.0
#: Reduced model, CPU seconds per design: the closed form (0.065-0.13 s per 10^6
#: designs) and the exact solver (0.037 s for 2 bristles, 0.24 s for 10 peristaltic).
REDUCED_CLOSED_FORM_S = 1.3e-7
REDUCED_EXACT_S = 0.24
#: Reduced exact solver, CPU seconds per cycle for N bristles: a N^2 + b N^3 in the
#: breathing gait (0.15 s for 100 bristles over 5 cycles, 1.8 s for 400, 20 s for 1,000
#: over 2 cycles, on a shared 2-core machine: rounded up), times REDUCED_PERISTALTIC in the
#: peristaltic gait (12.8 s for 400 bristles over one cycle), whose stick/slip events
#: also add about REDUCED_SAMPLES_PER_N2 N^2 samples per cycle to its record.
REDUCED_CYCLE_S_N2, REDUCED_CYCLE_S_N3 = 2e-6, 1e-8
REDUCED_PERISTALTIC = 15.0
REDUCED_SAMPLES_PER_N2 = 1.5
#: Bytes a reduced run keeps per sample and bristle (positions, forces, states).
REDUCED_BYTES = 32.0
#: CPU time past which one reduced run is refused, s: the exact solver is for designs of
#: seconds, and a run of hours is a design with far too many bristles.
MAX_REDUCED_S = 600.0
#: Memory of one Dask worker process: 270 MB with JAX and the models imported, doubled
#: for a compiled FE model and its records.
WORKER_BYTES = 0.55e9
#: Bytes a sweep keeps per design (its values, its outputs and status when gathered, its
#: part of the tasks in flight; rounded up).
DESIGN_BYTES = 1e3
#: Disk a sweep writes: a part file per task (3.9 kB for one design, 261 kB for 1,000)
#: and the gathered store.
PART_BYTES, PART_BYTES_PER_DESIGN, STORE_BYTES_PER_DESIGN = 4e3, 260.0, 250.0
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
    disk: float = 0.0
    workers: int = 0

    def text(self) -> str:
        time = f", {duration(self.seconds)} of CPU time" if self.seconds else ""
        if self.seconds and self.workers > 1:
            time += f" ({duration(self.seconds / self.workers)} on {self.workers} workers)"
        disk = f", {_bytes(self.disk)} of disk" if self.disk else ""
        return (
            f"{self.what}: about {_count(self.steps)} {self.unit}{time}, "
            f"{_bytes(self.memory)} of memory{disk}"
        )

    def check(
        self, max_steps: float | None = MAX_STEPS, where: str = ".", max_seconds: float = math.inf
    ) -> Estimate:
        """InputError, with the estimate, where the machine cannot hold the work (or it
        would take more than ``max_seconds`` of CPU time)."""
        limit = machine_memory()
        if not (self.memory <= 0.8 * limit):
            raise InputError(
                f"{self.text()}: more than this machine's {_bytes(limit)} can hold; "
                "make the work smaller"
            )
        free = _free_disk(where)
        if self.disk and not (self.disk <= 0.9 * free):
            raise InputError(
                f"{self.text()}: more than the {_bytes(free)} free on the disk; make the work "
                "smaller (or its tasks larger: chunk)"
            )
        if max_steps is not None and not (self.steps <= max_steps):
            raise InputError(
                f"{self.text()}: more than {max_steps:g} {self.unit}; make the work smaller"
            )
        if not (self.seconds <= max_seconds):
            raise InputError(
                f"{self.text()}: more than {duration(max_seconds)} of CPU time; make the "
                "work smaller"
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


def reduced_run(bristles: int, cycles: int, samples_per_cycle: int, gait: str) -> Estimate:
    """One run of the reduced model's exact solver (see :data:`REDUCED_CYCLE_S_N2`)."""
    n = float(bristles)
    seconds = cycles * (REDUCED_CYCLE_S_N2 * n**2 + REDUCED_CYCLE_S_N3 * n**3)
    samples = float(samples_per_cycle)
    if gait == "peristaltic":
        seconds *= REDUCED_PERISTALTIC
        samples += REDUCED_SAMPLES_PER_N2 * n**2
    samples *= cycles
    what = f"the reduced model with {bristles:,} bristles"
    return Estimate(what, samples, "samples", seconds, samples * n * REDUCED_BYTES)


def study(
    name: str, designs: int, tasks: int, design_s: float, workers: int, compile_s: float
) -> Estimate:
    """A design study of ``designs`` designs in ``tasks`` tasks, ``design_s`` CPU seconds
    each, on ``workers`` workers (0: a scheduler's, unknown) that compile for
    ``compile_s`` s each."""
    seconds = designs * design_s + max(workers, 1) * compile_s
    memory = designs * DESIGN_BYTES + workers * WORKER_BYTES
    disk = tasks * PART_BYTES + designs * (PART_BYTES_PER_DESIGN + STORE_BYTES_PER_DESIGN)
    return Estimate(f"study {name}", designs, "designs", seconds, memory, disk, workers)


def _free_disk(where: str) -> float:
    path = os.path.abspath(where)
    while not os.path.isdir(path) and os.path.dirname(path) != path:
        path = os.path.dirname(path)
    try:
        st = os.statvfs(path)
    except (OSError, AttributeError):
        return math.inf
    return float(st.f_bavail * st.f_frsize)


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
