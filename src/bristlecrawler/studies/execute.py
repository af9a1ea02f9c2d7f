"""Dask execution: one task per design (fe) or per chunk of designs (reduced).

The client connects to a running scheduler (``tcp://host:port``: dask-jobqueue on SLURM
or PBS, Kubernetes, a cloud service) or starts a ``LocalCluster`` of processes, one
single-threaded worker per core (the FE solver is not thread-parallel per design, and
JAX in one process per worker keeps each worker's compiled programs to itself). A
worker that dies has its task rerun elsewhere by the scheduler
(``distributed.scheduler.allowed-failures``); only when those retries are spent are the
task's designs recorded as lost.
"""

from __future__ import annotations

import contextlib
import itertools
import logging
import os
import re
import time
from collections.abc import Callable, Iterable
from dataclasses import dataclass
from typing import Any

import numpy as np

from bristlecrawler.errors import InputError
from bristlecrawler.studies.evaluate import OUTPUTS, DesignStatus, one_line

CONNECT_TIMEOUT_S = 15.0


def fe_task(base: dict[str, Any], overrides: list[dict[str, Any]]) -> dict[str, np.ndarray]:
    """Run FE designs (the base scenario with each design's overrides) on a worker."""
    from bristlecrawler.fe import enable_compilation_cache
    from bristlecrawler.studies.designs import with_overrides
    from bristlecrawler.studies.evaluate import evaluate_fe

    enable_compilation_cache()
    n = len(overrides)
    res = {k: np.full(n, np.nan) for k in OUTPUTS}
    status = np.full(n, int(DesignStatus.DONE), np.int8)
    error = [""] * n
    for i, ov in enumerate(overrides):
        t0 = time.perf_counter()
        try:
            for k, v in evaluate_fe(with_overrides(base, ov)).items():
                res[k][i] = v
        except Exception as exc:  # a failed design is recorded, the others go on
            status[i], error[i] = DesignStatus.FAILED, one_line(exc)
        res["wall_time_s"][i] = time.perf_counter() - t0
    return res | {"status": status, "error": np.asarray(error, dtype=str)}


def fe_batch_task(
    base: dict[str, Any], overrides: list[dict[str, Any]], width: int
) -> dict[str, np.ndarray]:
    """Run FE designs of one structure as one batch (:func:`crawler.run_batch`) on a
    worker; the batch's wall time is shared evenly by its designs."""
    from bristlecrawler.fe import enable_compilation_cache
    from bristlecrawler.studies.designs import with_overrides
    from bristlecrawler.studies.evaluate import evaluate_fe_batch

    enable_compilation_cache()
    n = len(overrides)
    res = {k: np.full(n, np.nan) for k in OUTPUTS}
    status = np.full(n, int(DesignStatus.DONE), np.int8)
    error = [""] * n
    t0 = time.perf_counter()
    try:
        outcomes = evaluate_fe_batch([with_overrides(base, ov) for ov in overrides], width)
    except Exception as exc:  # the batch could not start: every design failed with it
        outcomes = [one_line(exc)] * n
    for i, out in enumerate(outcomes):
        if isinstance(out, str):
            status[i], error[i] = DesignStatus.FAILED, out
        else:
            for k, v in out.items():
                res[k][i] = v
    res["wall_time_s"][:] = (time.perf_counter() - t0) / n
    return res | {"status": status, "error": np.asarray(error, dtype=str)}


def reduced_task(
    base: dict[str, Any], values: dict[str, np.ndarray], solver: str
) -> dict[str, np.ndarray]:
    """Evaluate a chunk of reduced designs on a worker."""
    from bristlecrawler.studies.evaluate import evaluate_reduced_chunk

    return evaluate_reduced_chunk(base, values, solver)


def lost_result(n: int, message: str) -> dict[str, np.ndarray]:
    """The record of a task whose designs could not be evaluated (worker lost)."""
    return {k: np.full(n, np.nan) for k in OUTPUTS} | {
        "status": np.full(n, int(DesignStatus.LOST), np.int8),
        "error": np.full(n, message[:500], dtype=object).astype(str),
    }


_ADDRESS = re.compile(
    r"(?:(?:tcp|tls|ws|wss|ucx)://)?(\[[0-9A-Fa-f:.]+\]|[A-Za-z0-9][A-Za-z0-9_.-]*):([0-9]{1,5})"
)


def check_address(scheduler: str) -> None:
    """InputError unless ``scheduler`` reads as a Dask scheduler's address,
    ``[protocol://]host:port`` (protocol tcp, tls, ws, wss or ucx): checked on sight, with
    no network wait."""
    m = _ADDRESS.fullmatch(scheduler)
    if m is None or not 0 < int(m.group(2)) < 65536:
        raise InputError(
            f"--scheduler {scheduler!r}"[:120] + " is not a Dask scheduler address: give "
            "[tcp://]host:port, e.g. tcp://127.0.0.1:8786"
        )


def connect(scheduler: str | None, workers: int | None, timeout_s: float = CONNECT_TIMEOUT_S):
    """A Dask client (and the LocalCluster it owns, or None). An unreachable scheduler,
    or one that does not answer, is an InputError after ``timeout_s`` seconds."""
    from distributed import Client, LocalCluster

    logging.getLogger("distributed").setLevel(logging.CRITICAL)
    if scheduler is not None:
        check_address(scheduler)
        return _client(Client, scheduler, timeout_s), None
    from bristlecrawler.studies.interrupt import IgnoreInterrupt, interrupt_ignored

    n = workers or os.cpu_count() or 1
    # Ctrl-C at a terminal reaches the workers too: they ignore it from their start on.
    with interrupt_ignored():
        cluster = LocalCluster(
            n_workers=n,
            threads_per_worker=1,
            processes=True,
            dashboard_address=":0",
            silence_logs=logging.ERROR,
        )
    client = Client(cluster, set_as_default=False)
    client.register_plugin(IgnoreInterrupt(), name="bristlecrawler-ignore-interrupt")
    return client, cluster


def _client(Client, scheduler: str, timeout_s: float):
    """Dask's own timeout covers the connection, not a handshake that never comes: the
    client is made in a daemon thread (which cannot hold up the exit), and given up when
    ``timeout_s`` has passed."""
    import threading

    got: dict[str, Any] = {}

    def make() -> None:
        try:
            got["client"] = Client(scheduler, timeout=timeout_s, set_as_default=False)
        except BaseException as exc:  # reported by the caller
            got["error"] = exc
        if got.get("late"):
            disconnect(got.get("client"), None)

    thread = threading.Thread(target=make, name="dask-connect", daemon=True)
    thread.start()
    thread.join(timeout_s + 1.0)
    if "client" in got:
        return got["client"]
    got["late"] = True
    exc = got.get("error")
    reason = (" ".join(str(exc).split())[:200] or type(exc).__name__) if exc else "no answer"
    raise InputError(
        f"cannot reach the Dask scheduler at {scheduler} within {timeout_s:g} s ({reason})"
    )


def disconnect(client, cluster) -> None:
    """Close the client, then its cluster, quietly: a worker's last heartbeat to a
    scheduler already gone is not news to the user."""
    logging.getLogger("distributed").setLevel(logging.CRITICAL)
    with contextlib.suppress(Exception):
        if client is not None:
            client.close()
    with contextlib.suppress(Exception):
        if cluster is not None:
            cluster.close()


@dataclass(frozen=True)
class Task:
    """One unit of work: its number, its designs' numbers, the function and arguments."""

    number: int
    index: np.ndarray
    fn: Callable
    args: tuple


def run_tasks(
    client, tasks: Iterable[Task], prefix: str, on_done, on_tick=None, window: int | None = None
) -> None:
    """Submit ``tasks`` and call ``on_done(task, result)`` in the client as each finishes
    (a lost task gets :func:`lost_result`); ``on_tick(running_designs)`` every 0.25 s.
    At most ``window`` tasks [default: four per worker thread, at least 64] are submitted
    at a time, so that a study of millions of tasks holds only those in memory."""
    from distributed import as_completed

    source = iter(tasks)
    if window is None:
        window = max(64, 4 * sum(client.nthreads().values()))
    futures, by_key = {}, {}
    pending = as_completed(loop=client.loop)

    def submit(count: int) -> None:
        for task in itertools.islice(source, count):
            fut = client.submit(task.fn, *task.args, key=f"{prefix}-{task.number}", pure=False)
            futures[fut], by_key[fut.key] = task, task
            pending.add(fut)

    submit(window)
    while futures:
        batch = pending.next_batch(block=False)
        for fut in batch:
            task = futures.pop(fut)
            by_key.pop(fut.key, None)
            if fut.status == "finished":
                on_done(task, fut.result())
            else:
                on_done(task, lost_result(task.index.size, f"task lost: {_why(fut)}"))
            fut.release()
        submit(len(batch))
        if not batch and on_tick is not None:
            on_tick(_running(client, by_key))
        if not batch:
            time.sleep(0.25)


def _why(fut) -> str:
    """Why a future ended without a result (KilledWorker, a scheduler gone, ...)."""
    try:
        exc = fut.exception(timeout=5)
    except Exception as other:  # cancelled or unreachable: that is the reason
        exc = other
    return one_line(exc) if exc is not None else f"task {fut.status}"


def _running(client, by_key) -> int:
    """Designs of the tasks that workers are running now (a worker's queue beyond its
    threads is waiting, not running)."""
    try:
        processing, threads = client.processing(), client.nthreads()
    except Exception:  # a scheduler that went away shows in the futures themselves
        return 0
    busy = 0
    for worker, keys in processing.items():
        ours = [by_key[k].index.size for k in keys if k in by_key]
        busy += sum(ours[: threads.get(worker, 1)])
    return busy
