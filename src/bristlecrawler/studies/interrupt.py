"""Ctrl-C and the local Dask workers: a terminal sends SIGINT to every process of its
group, the workers included. They ignore it, so that the client alone answers it (saying
what was kept, with no traceback) and closes them. Imported only where a local cluster is
started: it imports ``distributed``."""

from __future__ import annotations

import contextlib
import signal

from distributed.diagnostics.plugin import WorkerPlugin


class IgnoreInterrupt(WorkerPlugin):
    """A worker's process ignores SIGINT (a worker restarted after a crash included)."""

    def setup(self, worker) -> None:
        with contextlib.suppress(ValueError):  # a worker not in its process's main thread
            signal.signal(signal.SIGINT, signal.SIG_IGN)


@contextlib.contextmanager
def interrupt_ignored():
    """SIGINT ignored in this process meanwhile: the processes it starts inherit that."""
    try:
        previous = signal.signal(signal.SIGINT, signal.SIG_IGN)
    except ValueError:  # not the main thread: signals are the main thread's
        yield
        return
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)
