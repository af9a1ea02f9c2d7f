"""Progress bar for long simulations: simulated time, wall time and ETA, on stderr (so that
``--json`` output on stdout stays clean); silent when disabled or not on a terminal."""

from __future__ import annotations

import contextlib
import sys
from collections.abc import Iterator


class _Null:
    def update(self, t_sim: float, stage: str | None = None, **info) -> None:
        """Do nothing."""


@contextlib.contextmanager
def sim_progress(t_end: float, label: str = "simulating", enabled: bool | None = None) -> Iterator:
    """Yield an object with ``update(t_sim, stage=None, **info)``: ``t_sim`` s of simulated
    time, ``stage`` what the run is doing (kept until the next stage), ``info`` counters."""
    if enabled is None:
        enabled = sys.stderr.isatty()
    if not enabled:
        yield _Null()
        return
    from rich.console import Console
    from rich.progress import (
        BarColumn,
        Progress,
        TextColumn,
        TimeElapsedColumn,
        TimeRemainingColumn,
    )

    progress = Progress(
        TextColumn("[bold]{task.description}"),
        BarColumn(bar_width=12),
        TextColumn("t = {task.completed:.1f}/{task.total:.1f} s"),
        TextColumn("{task.fields[info]}"),
        TimeElapsedColumn(),
        TextColumn("ETA"),
        TimeRemainingColumn(),
        console=Console(stderr=True),
        transient=False,
    )
    task = progress.add_task(label, total=t_end, info="")

    class _Bar:
        stage = ""

        def update(self, t_sim: float, stage: str | None = None, **info) -> None:
            if stage is not None:
                self.stage = stage
            text = " ".join([self.stage, *(f"{k}={v}" for k, v in info.items())])
            progress.update(task, completed=min(t_sim, t_end), info=text.strip())

    with progress:
        yield _Bar()
