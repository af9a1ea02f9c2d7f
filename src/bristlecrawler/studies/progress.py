"""Progress of a sweep on stderr: a bar with designs done, failed, running and an ETA on a
terminal; without one (a batch job's log), one line per finished design (per finished
task for chunks of reduced designs).

The ETA comes from the finished designs' own measured wall times (the median, so that the
first design of each worker, which compiles, does not dominate), spread over the workers.
"""

from __future__ import annotations

import statistics
import sys
import time

from bristlecrawler.errors import printable


def eta_seconds(left: int, design_seconds: list[float], workers: int) -> float | None:
    """Seconds until ``left`` designs are done on ``workers`` workers at the median of the
    measured ``design_seconds``; None before any design was measured."""
    measured = [s for s in design_seconds if s == s and s >= 0]
    if left <= 0:
        return 0.0
    if not measured:
        return None
    per_design = statistics.median(measured)
    rounds = -(-left // max(workers, 1))  # designs run ``workers`` at a time
    return rounds * per_design


def format_eta(seconds: float | None) -> str:
    if seconds is None:
        return "ETA: after the first design"
    if seconds >= 86400:
        return "ETA: more than a day"
    return "ETA " + time.strftime("%H:%M:%S", time.gmtime(seconds))


class SweepProgress:
    """``finished(text, n, failed, seconds)`` after each task (``seconds``: its designs'
    measured wall times), ``running(n)`` between them."""

    def __init__(
        self, total: int, done: int, failed: int, enabled: bool | None = None, workers: int = 1
    ):
        from bristlecrawler.viz.progress import progress_mode

        self.total, self.done, self.failed, self.busy = total, done, failed, 0
        self.workers = workers
        self.seconds: list[float] = []
        self.mode = progress_mode(enabled)
        self._bar = None
        if self.mode == "bars":
            from rich.console import Console
            from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn

            self._bar = Progress(
                TextColumn("[bold]sweep"),
                BarColumn(bar_width=20),
                TextColumn("{task.fields[text]}"),
                TimeElapsedColumn(),
                console=Console(stderr=True),
            )
            self._task = self._bar.add_task("sweep", total=total, completed=done, text="")
            self._bar.start()
            self._refresh()

    def eta(self) -> str:
        return format_eta(eta_seconds(self.total - self.done, self.seconds, self.workers))

    def _refresh(self) -> None:
        text = f"{self.done}/{self.total} finished, {self.failed} failed, {self.busy} running"
        if self.done < self.total:
            text += f", {self.eta()}"
        self._bar.update(self._task, completed=self.done, text=text)

    def running(self, n: int) -> None:
        self.busy = n
        if self._bar is not None:
            self._refresh()

    def finished(self, text: str, n: int, failed: int, seconds: list[float] = ()) -> None:
        self.done += n
        self.failed += failed
        self.seconds += list(seconds)
        if self.done >= self.total:
            self.busy = 0
        if self._bar is not None:
            self._refresh()
            return
        if self.mode == "off":
            return
        left = "" if self.done >= self.total else f", {self.eta()}"
        line = printable(f"[{self.done}/{self.total}] {text}{left}")
        print(line, file=sys.stderr, flush=True)

    def close(self) -> None:
        if self._bar is not None:
            self._bar.stop()
