"""Progress of long simulations on stderr (so that ``--json`` output on stdout stays clean).

On a terminal: a bar with the simulated time, wall time and ETA. Elsewhere (a pipe, a log
file, a batch job): one line per stage (compiling, gravity step, modal analysis) and one
each time the run passes a mark of simulated time (every cycle when the caller gives the
cycle period, else every tenth of the run). Disabled: silent. A stage can come with a note
(what it is and how long it is expected to take), printed as a line of its own when the
stage starts, and its measured time when it ends, in either form. A long command announces
itself first, in one line (:func:`announce`).
"""

from __future__ import annotations

import contextlib
import math
import sys
import time
from collections.abc import Callable, Iterator, Mapping
from dataclasses import dataclass
from typing import Literal

Mode = Literal["bars", "lines", "off"]


def announce(label: str, text: str) -> None:
    """One line on stderr, before the work starts (``label: text``); the text names the
    run's folder, as given: escaped, it cannot send a control sequence to the terminal."""
    from bristlecrawler.errors import printable

    print(printable(f"{label}: {text}"), file=sys.stderr, flush=True)


def progress_mode(enabled: bool | None, stream=None) -> Mode:
    """How to show progress: ``enabled`` True bars, False nothing, None (the default of
    every command) bars when ``stream`` (stderr) is a terminal and lines otherwise."""
    if enabled is None:
        stream = sys.stderr if stream is None else stream
        isatty = getattr(stream, "isatty", None)
        return "bars" if isatty is not None and isatty() else "lines"
    return "bars" if enabled else "off"


@dataclass(frozen=True)
class StageNote:
    """A stage's lines that are only known as it runs: ``start()`` when it starts,
    ``end(seconds)`` when it ends (what it turned out to do, and how long it took)."""

    start: Callable[[], str]
    end: Callable[[float], str]


class StageNotes:
    """Prints ``notes[stage]`` when a stage that has a note starts, and the stage's
    measured time when it ends (``write(text)`` prints one line); a :class:`StageNote`
    writes its own lines."""

    def __init__(self, notes: Mapping[str, str | StageNote] | None, write) -> None:
        self.notes, self.write = dict(notes or {}), write
        self.current: str | None = None
        self.t0 = 0.0

    def enter(self, stage: str) -> None:
        if stage == self.current:
            return
        note = self.notes.get(self.current)
        if note is not None:
            took = time.perf_counter() - self.t0
            ended = note.end(took) if isinstance(note, StageNote) else None
            self.write(ended or f"{self.current}: done in {took:.0f} s")
        self.current, self.t0 = stage, time.perf_counter()
        note = self.notes.get(stage)
        if note is not None:
            self.write(note.start() if isinstance(note, StageNote) else note)


def stderr_bars(*columns, tail=()):
    """A rich ``Progress`` on stderr with ``columns``, then the elapsed time and the ETA,
    then ``tail`` columns."""
    from rich.console import Console
    from rich.progress import Progress, TextColumn, TimeElapsedColumn, TimeRemainingColumn

    eta = (TimeElapsedColumn(), TextColumn("ETA"), TimeRemainingColumn())
    return Progress(*columns, *eta, *tail, console=Console(stderr=True), transient=False)


class _Null:
    def update(self, t_sim: float, stage: str | None = None, **info) -> None:
        """Do nothing."""


class _Lines:
    """One line per stage and per mark of simulated time, for logs."""

    def __init__(
        self, t_end: float, label: str, period: float | None, start: float, stream, notes=None
    ):
        self.t_end, self.label, self.stream = t_end, label, stream
        self.period, self.start = period, start
        self.wall0 = time.perf_counter()
        self.stage: str | None = None
        self.mark = 0  # marks passed so far
        self.notes = StageNotes(notes, lambda text: print(text, file=stream, flush=True))

    def _step(self) -> float:
        return self.period if self.period else self.t_end / 10.0

    def _write(self, text: str) -> None:
        elapsed = time.perf_counter() - self.wall0
        print(f"{self.label}: {text} ({elapsed:.0f} s elapsed)", file=self.stream, flush=True)

    def update(self, t_sim: float, stage: str | None = None, **info) -> None:
        if stage is not None and stage != self.stage:
            self.stage = stage
            self.notes.enter(stage)
            self._write(f"{stage or 'stepping'} at t = {t_sim:.3g} s")
        origin = self.start if self.period else 0.0
        step = self._step()
        if step <= 0 or not math.isfinite(step):
            return
        passed = int((t_sim - origin) / step + 1e-9)
        if passed > self.mark:
            self.mark = passed
            what = f"cycle {passed} done" if self.period else f"{passed * 10} %"
            counters = ", ".join(f"{k} {v}" for k, v in info.items())
            extra = f", {counters}" if counters else ""
            self._write(f"{what}, t = {t_sim:.4g}/{self.t_end:.4g} s{extra}")


@contextlib.contextmanager
def sim_progress(
    t_end: float,
    label: str = "simulating",
    enabled: bool | None = None,
    period: float | None = None,
    start: float = 0.0,
    notes: Mapping[str, str | StageNote] | None = None,
) -> Iterator:
    """Yield an object with ``update(t_sim, stage=None, **info)``: ``t_sim`` s of simulated
    time, ``stage`` what the run is doing (kept until the next stage), ``info`` counters.

    ``enabled``: see :func:`progress_mode`. ``period`` (s) and ``start`` (s, when the first
    cycle starts): report each cycle's end in the lines; without them every tenth of
    ``t_end`` is reported. ``notes``: a line to print when a stage starts, by stage name.
    """
    mode = progress_mode(enabled)
    if mode == "lines":
        yield _Lines(t_end, label, period, start, sys.stderr, notes)
        return
    if mode == "off":
        yield _Null()
        return
    from rich.progress import BarColumn, TextColumn

    progress = stderr_bars(
        TextColumn("[bold]{task.description}"),
        BarColumn(bar_width=12),
        TextColumn("t = {task.completed:.1f}/{task.total:.1f} s"),
        TextColumn("{task.fields[info]}"),
    )
    task = progress.add_task(label, total=t_end, info="")

    stage_notes = StageNotes(
        notes, lambda text: progress.console.print(text, markup=False, highlight=False)
    )

    class _Bar:
        stage = ""

        def update(self, t_sim: float, stage: str | None = None, **info) -> None:
            if stage is not None:
                self.stage = stage
                stage_notes.enter(stage)
            text = " ".join([self.stage, *(f"{k}={v}" for k, v in info.items())])
            progress.update(task, completed=min(t_sim, t_end), info=text.strip())

    with progress:
        yield _Bar()
