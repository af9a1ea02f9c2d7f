"""Progress of a run made of parts (``bristlecrawler reproduce``), on stderr.

On a terminal: a bar for the whole run, weighted by each part's expected time, with its
ETA and the part it is in, and a bar per part. Elsewhere: one line as each part starts
(with the time left) and ends. Disabled: silent.
"""

from __future__ import annotations

import contextlib
import sys
import time
from collections.abc import Iterator


class _Null:
    def start(self, name: str) -> None:
        """Do nothing."""

    def update(self, fraction: float) -> None:
        """Do nothing."""

    def finish(self, name: str, ok: bool, wall_s: float) -> None:
        """Do nothing."""

    def note(self, text: str) -> None:
        """Do nothing."""


#: Share of the expected time done before the run's own pace scales what is left (a
#: first part of a second says little of the FE parts after it).
ETA_AFTER = 0.1
#: A running part's time alone counts for at most this share of its expected cost.
TIME_SHARE_CAP = 0.95
#: Bounds of the pace (this run's time over the expected) that scales what is left.
PACE_BOUNDS = (0.2, 20.0)


class Overall:
    """The whole run's progress and ETA, weighted by each part's expected cost (s: its
    last run here, or the reference machine's time).

    A running part counts as done by the larger of what it reports (its simulated time)
    and its time so far over its expected cost (at most :data:`TIME_SHARE_CAP`): compiling
    reports nothing, but it is work, and the bar moves through it. What is left is the
    expected cost of the rest, scaled by this run's pace (its time over the expected cost
    of what it has done) once that is :data:`ETA_AFTER` of the whole. ``clock``: seconds,
    monotonic (a test passes its own)."""

    def __init__(self, costs: dict[str, float], clock=time.monotonic) -> None:
        self.costs, self.clock = dict(costs), clock
        self.total = sum(self.costs.values())
        self.spent = 0.0  # wall time of the finished parts, s
        self.expected_done = 0.0  # their expected cost, s
        self.current: str | None = None
        self.t_start = 0.0
        self.fraction = 0.0

    def start(self, name: str) -> None:
        self.current, self.t_start, self.fraction = name, self.clock(), 0.0

    def update(self, fraction: float) -> None:
        self.fraction = min(max(fraction, 0.0), 1.0)

    def finish(self, name: str, wall_s: float) -> None:
        self.spent += wall_s
        self.expected_done += self.costs.get(name, 0.0)
        self.current = None

    def share(self, now: float) -> float:
        """How much of the running part is done, 0 to 1."""
        cost = self.costs.get(self.current, 0.0) if self.current else 0.0
        if cost <= 0.0:
            return self.fraction
        return max(self.fraction, min((now - self.t_start) / cost, TIME_SHARE_CAP))

    def done(self, now: float | None = None) -> float:
        """The expected seconds' worth of work done."""
        now = self.clock() if now is None else now
        running = self.costs.get(self.current, 0.0) if self.current else 0.0
        return self.expected_done + running * self.share(now)

    def eta(self, now: float | None = None) -> float:
        """Seconds left."""
        now = self.clock() if now is None else now
        done = self.done(now)
        spent = self.spent + (now - self.t_start if self.current else 0.0)
        pace = 1.0
        if done >= ETA_AFTER * self.total and done > 0:
            pace = min(max(spent / done, PACE_BOUNDS[0]), PACE_BOUNDS[1])
        return pace * max(self.total - done, 0.0)

    def where(self) -> str:
        """Which part the run is in."""
        if self.current is None:
            return ""
        names = list(self.costs)
        return f"in {self.current} ({names.index(self.current) + 1} of {len(names)})"


def _clock_text(seconds: float) -> str:
    seconds = round(seconds)
    h, rest = divmod(seconds, 3600)
    return f"{h}:{rest // 60:02d}:{rest % 60:02d}"


class _Lines(_Null):
    def __init__(self, label: str, overall: Overall, stream) -> None:
        self.label, self.overall, self.stream = label, overall, stream
        self.wall0 = overall.clock()

    def _write(self, text: str) -> None:
        print(f"{self.label}: {text}", file=self.stream, flush=True)

    def start(self, name: str) -> None:
        self.overall.start(name)
        now = self.overall.clock()
        left = self.overall.eta(now)
        self._write(f"{name} ... ({now - self.wall0:.0f} s elapsed, about {left:.0f} s left)")

    def update(self, fraction: float) -> None:
        self.overall.update(fraction)

    def note(self, text: str) -> None:
        self._write(text)

    def finish(self, name: str, ok: bool, wall_s: float) -> None:
        self.overall.finish(name, wall_s)
        self._write(f"{name} {'done' if ok else 'FAILED'} in {wall_s:.0f} s")


@contextlib.contextmanager
def parts_progress(
    costs: dict[str, float],
    label: str = "reproduce",
    enabled: bool | None = None,
    clock=time.monotonic,
) -> Iterator:
    """Yield an object with ``start(name)``, ``update(fraction)`` (of the running part,
    0 to 1), ``note(text)`` and ``finish(name, ok, wall_s)``. ``costs``: each part's
    expected time (s), in order (see :class:`Overall`). ``enabled``: True bars, False
    nothing, None bars on a terminal and lines elsewhere."""
    from bristlecrawler.viz.progress import progress_mode

    overall = Overall(costs, clock)
    mode = progress_mode(enabled)
    if mode == "lines":
        yield _Lines(label, overall, sys.stderr)
        return
    if mode == "off":
        yield _Null()
        return
    with _bars(label, overall) as bars:
        yield bars


class _OverallColumns:
    """Columns that draw the whole run's row from :class:`Overall` (at each redraw) and
    each part's row from its own task."""

    def __init__(self, overall: Overall) -> None:
        self.overall = overall
        self.task = None  # the whole run's task id

    def _fraction(self, task) -> float:
        o = self.overall
        if task.id != self.task:
            running = task.description == o.current
            return o.share(o.clock()) if running else task.percentage / 100.0
        total = self.overall.total
        return min(self.overall.done() / total, 1.0) if total > 0 else 0.0

    def _column(self, render):
        from rich.progress import ProgressColumn

        class _Column(ProgressColumn):
            def render(self, task):
                return render(task)

        return _Column()

    def bar(self):
        import dataclasses

        from rich.progress import BarColumn

        inner = BarColumn(bar_width=24)

        def render(task):
            if task.id == self.task:
                task = dataclasses.replace(task, total=1.0, completed=self._fraction(task))
            return inner.render(task)

        return self._column(render)

    def percent(self):
        from rich.text import Text

        return self._column(lambda task: Text(f"{100.0 * self._fraction(task):>3.0f} %"))

    def eta(self):
        from rich.text import Text

        def render(task):
            o = self.overall
            if task.id == self.task:
                return Text(f"ETA {_clock_text(o.eta())}   {o.where()}".rstrip())
            if task.description != o.current:
                return Text("")
            left = o.costs[o.current] * (1.0 - o.share(o.clock()))
            return Text(f"ETA {_clock_text(left)}")

        return self._column(render)


@contextlib.contextmanager
def _bars(label: str, overall: Overall) -> Iterator:
    """Rich bars: the whole run's (its share and ETA from :class:`Overall`, read from the
    clock at each redraw, so they move while a part compiles) and one per part."""
    from rich.console import Console
    from rich.progress import Progress, TextColumn, TimeElapsedColumn

    whole = _OverallColumns(overall)
    progress = Progress(
        TextColumn("[bold]{task.description:<12}"),
        whole.bar(),
        whole.percent(),
        TimeElapsedColumn(),
        whole.eta(),
        TextColumn("{task.fields[note]}"),
        console=Console(stderr=True),
        transient=False,
    )
    whole.task = progress.add_task(label, total=1.0, note="")
    tasks = {n: progress.add_task(n, total=1.0, start=False, note="") for n in overall.costs}

    class _Bars(_Null):
        def start(self, name: str) -> None:
            overall.start(name)
            progress.start_task(tasks[name])

        def update(self, fraction: float) -> None:
            if overall.current is not None:
                overall.update(fraction)
                progress.update(tasks[overall.current], completed=overall.fraction)

        def note(self, text: str) -> None:
            progress.console.print(f"{label}: {text}", markup=False, highlight=False)

        def finish(self, name: str, ok: bool, wall_s: float) -> None:
            overall.finish(name, wall_s)
            progress.update(tasks[name], completed=1.0, note="done" if ok else "FAILED")
            progress.stop_task(tasks[name])

    with progress:
        yield _Bars()
