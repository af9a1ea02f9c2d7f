"""Progress of a run made of parts (``bristlecrawler reproduce``), on stderr.

On a terminal: a rich bar per part and one for the whole run, each with its ETA (the
whole run's from the parts' expected shares of the time). Elsewhere: one line as each part
starts and ends. Disabled: silent.
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


#: Share of the expected time done before the lines extrapolate an ETA from nominal costs
#: (a first part of a second says nothing about the FE parts after it).
ETA_AFTER = 0.25


class _Lines(_Null):
    def __init__(self, label: str, costs: dict[str, float], stream, measured: bool) -> None:
        self.label, self.costs, self.stream, self.measured = label, costs, stream, measured
        self.wall0 = time.perf_counter()
        self.done = 0.0

    def _write(self, text: str) -> None:
        print(f"{self.label}: {text}", file=self.stream, flush=True)

    def start(self, name: str) -> None:
        elapsed = time.perf_counter() - self.wall0
        total = sum(self.costs.values())
        eta = ""
        if self.measured:
            eta = f", about {total - self.done:.0f} s left by earlier runs here"
        elif self.done >= ETA_AFTER * total:
            eta = f", about {elapsed * (total - self.done) / self.done:.0f} s left"
        self._write(f"{name} ... ({elapsed:.0f} s elapsed{eta})")

    def note(self, text: str) -> None:
        self._write(text)

    def finish(self, name: str, ok: bool, wall_s: float) -> None:
        self.done += self.costs.get(name, 0.0)
        self._write(f"{name} {'done' if ok else 'FAILED'} in {wall_s:.0f} s")


@contextlib.contextmanager
def parts_progress(
    costs: dict[str, float],
    label: str = "reproduce",
    enabled: bool | None = None,
    measured: bool = False,
) -> Iterator:
    """Yield an object with ``start(name)``, ``update(fraction)`` (of the running part,
    0 to 1) and ``finish(name, ok, wall_s)``. ``costs``: each part's expected share of
    the time, in order; ``measured``: they are seconds measured in earlier runs.
    ``enabled``: True bars, False nothing, None bars on a terminal and lines elsewhere."""
    from bristlecrawler.viz.progress import progress_mode, stderr_bars

    mode = progress_mode(enabled)
    if mode == "lines":
        yield _Lines(label, costs, sys.stderr, measured)
        return
    if mode == "off":
        yield _Null()
        return
    from rich.progress import BarColumn, TextColumn

    progress = stderr_bars(
        TextColumn("[bold]{task.description:<12}"),
        BarColumn(bar_width=24),
        TextColumn("{task.percentage:>3.0f} %"),
        tail=(TextColumn("{task.fields[note]}"),),
    )
    total = progress.add_task(label, total=sum(costs.values()), note="")
    tasks = {n: progress.add_task(n, total=1.0, start=False, note="") for n in costs}

    class _Bars(_Null):
        current: str | None = None
        base = 0.0

        def start(self, name: str) -> None:
            self.current = name
            progress.start_task(tasks[name])

        def update(self, fraction: float) -> None:
            if self.current is None:
                return
            f = min(max(fraction, 0.0), 1.0)
            progress.update(tasks[self.current], completed=f)
            progress.update(total, completed=self.base + f * costs[self.current])

        def note(self, text: str) -> None:
            progress.console.print(f"{label}: {text}", markup=False, highlight=False)

        def finish(self, name: str, ok: bool, wall_s: float) -> None:
            self.base += costs[name]
            note = "done" if ok else "FAILED"
            progress.update(tasks[name], completed=1.0, note=note)
            progress.stop_task(tasks[name])
            progress.update(total, completed=self.base)
            self.current = None

    with progress:
        yield _Bars()
