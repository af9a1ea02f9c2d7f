"""What a part of the reproduction is: a name, a run of the context, a result.

The report is a tuple of :class:`Part` objects run in order. Each one reads what it needs
from the :class:`Context` (the settings, the output folder, the results of the parts before
it) and returns a :class:`PartResult`: numbers for the table, figures, and lines of text.
A part that fails is a :class:`PartResult` too, with the reason, so one failing solver
costs its own section and not the report. Adding a section is adding a Part.
"""

from __future__ import annotations

import dataclasses
import math
import time
import traceback
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from bristlecrawler.errors import InputError, Interrupted, SolverError


@dataclass(frozen=True)
class Settings:
    """How much to compute. ``quick`` trades resolution for time (the tests use it).

    Attributes:
        quick: the short version (fewer cycles, fewer starting places, shorter drag legs).
        fe_cycles: cycles of the FE crawler at alpha = pi/4.
        elements: beam elements per bristle (the paper's scenario has 20).
        vertical_phases: starting places of the tips on the texture at alpha = 0, evenly
            spaced over one groove pitch; one cycle each.
        drag_distance: travel of each leg of the drag test, mm.
        study_fe: whether the design study includes the FE inclination sweep.
        workers: Dask workers of the design study's local cluster.
        frames_per_cycle: frames of the animation per cycle.
    """

    quick: bool = False
    fe_cycles: int = 5
    elements: int = 20
    vertical_phases: int = 8
    drag_distance: float = 10.0
    study_fe: bool = True
    workers: int = 2
    frames_per_cycle: int = 24

    @classmethod
    def full(cls) -> Settings:
        return cls()

    @classmethod
    def short(cls) -> Settings:
        """The ``--quick`` settings: one cycle, one starting place at alpha = 0, 4 mm drag
        legs, on the full run's mesh (20 elements per bristle), so its programs are the full
        run's (the drag's path and the stroke are values of them). At 6 elements it compiled
        about as long, and its one cycle at alpha = 0 advanced 7.5 mm against 1.5 mm at 20."""
        return cls(
            quick=True,
            fe_cycles=1,
            elements=20,
            vertical_phases=1,
            drag_distance=4.0,
            study_fe=False,
            workers=1,
            frames_per_cycle=12,
        )


@dataclass(frozen=True)
class Figure:
    """A file the part wrote (relative to the report's folder) and its caption."""

    path: str
    caption: str


@dataclass(frozen=True)
class PartResult:
    """What a part found.

    Attributes:
        name: the part's name.
        ok: False when the part failed; ``error`` then says why.
        values: numbers for the table and the JSON (units in the keys), None where a
            quantity is not available.
        figures: the figures and animations it wrote.
        lines: Markdown lines describing what was run and found (no figures, no headings).
        wall_s: how long the part took, s.
        error: one line, the reason of a failure.
    """

    name: str
    ok: bool = True
    values: dict[str, Any] = field(default_factory=dict)
    figures: tuple[Figure, ...] = ()
    lines: tuple[str, ...] = ()
    wall_s: float = math.nan
    error: str = ""


@dataclass
class Context:
    """What the parts share: the settings, the folder they write into, the inputs read at
    the edge (the recording), the results so far, the progress callback
    (``progress(fraction)`` with the running part's fraction done, 0 to 1) and ``note``,
    a line for the user (what a long step is doing, how long it should take)."""

    settings: Settings
    folder: Path
    inputs: dict[str, Any] = field(default_factory=dict)
    results: dict[str, PartResult] = field(default_factory=dict)
    progress: Callable[[float], None] = lambda fraction: None
    note: Callable[[str], None] = lambda text: None

    def value(self, part: str, key: str) -> Any:
        """A number another part found, or None (that part failed or did not run)."""
        r = self.results.get(part)
        return None if r is None or not r.ok else r.values.get(key)


@dataclass(frozen=True)
class Part:
    """One section of the report.

    Attributes:
        name: short identifier (file prefixes, JSON keys).
        title: the section's heading.
        run: the computation, ``run(ctx) -> PartResult``.
        cost: its time on the reference machine (an idle 2-core machine, an empty
            compilation cache), s: what the overall bar and ETA expect until the part has
            run here. quick_cost: the same with ``--quick`` (None: ``cost``).
    """

    name: str
    title: str
    run: Callable[[Context], PartResult]
    cost: float = 1.0
    quick_cost: float | None = None

    def reference_seconds(self, settings: Settings) -> float:
        """Its expected time on the reference machine with ``settings``, s."""
        if settings.quick and self.quick_cost is not None:
            return self.quick_cost
        return self.cost


def run_part(part: Part, ctx: Context) -> PartResult:
    """Run ``part``; a solver failure or an unexpected error becomes a failed result with a
    one-line reason (the report still gets written). Ctrl-C is not caught."""
    t0 = time.perf_counter()
    try:
        result = part.run(ctx)
    except (KeyboardInterrupt, Interrupted):
        raise
    except SolverError as exc:
        result = PartResult(part.name, ok=False, error=f"solver failed: {_one_line(exc)}")
    except InputError as exc:
        result = PartResult(part.name, ok=False, error=_one_line(exc))
    except Exception as exc:  # a bug or a library failure: say where, keep the report
        where = traceback.extract_tb(exc.__traceback__)[-1]
        place = f" ({Path(where.filename).name}:{where.lineno})"
        result = PartResult(
            part.name, ok=False, error=f"{type(exc).__name__}: {_one_line(exc)}{place}"
        )
    return dataclasses.replace(result, wall_s=time.perf_counter() - t0)


def _one_line(exc: BaseException) -> str:
    return " ".join(str(exc).split()) or type(exc).__name__
