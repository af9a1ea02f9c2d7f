"""Progress of a sweep on stderr: a bar with designs done, failed, running and an ETA on a
terminal; without one (a batch job's log), one line per finished design (per finished
task for chunks of reduced designs)."""

from __future__ import annotations

import sys
import time


class SweepProgress:
    """``finished(text, done, failed)`` after each task, ``running(n)`` between them."""

    def __init__(self, total: int, done: int, failed: int, enabled: bool | None = None):
        self.total, self.done, self.failed, self.busy = total, done, failed, 0
        self.start_done = done
        self.t0 = time.perf_counter()
        tty = sys.stderr.isatty() if enabled is None else enabled
        self._bar = None
        if tty:
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
        new = self.done - self.start_done
        if new <= 0 or self.done >= self.total:
            return "-"
        rate = new / (time.perf_counter() - self.t0)
        seconds = (self.total - self.done) / rate
        return time.strftime("%H:%M:%S", time.gmtime(seconds)) if seconds < 86400 else ">1 d"

    def _refresh(self) -> None:
        text = (
            f"{self.done}/{self.total} done, {self.failed} failed, {self.busy} running, "
            f"ETA {self.eta()}"
        )
        self._bar.update(self._task, completed=self.done, text=text)

    def running(self, n: int) -> None:
        self.busy = n
        if self._bar is not None:
            self._refresh()

    def finished(self, text: str, n: int, failed: int) -> None:
        self.done += n
        self.failed += failed
        if self.done >= self.total:
            self.busy = 0
        if self._bar is not None:
            self._refresh()
            return
        print(f"[{self.done}/{self.total}] {text} (ETA {self.eta()})", file=sys.stderr, flush=True)

    def close(self) -> None:
        if self._bar is not None:
            self._bar.stop()
