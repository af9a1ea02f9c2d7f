"""A sweep from start to end: check everything, run what is left on Dask, gather, plot.

1. Load the study, resolve its base, expand and validate every design (one line, exit 2
   on the first bad one: nothing written).
2. Check the output folder (another study's results, or this one's without resume, are
   refused) and connect to the scheduler (unreachable: refused), still before writing.
3. Submit the tasks that have no part file yet; write each task's part as it finishes.
4. Gather the parts into ``study.zarr`` (and ``designs.csv``), draw the figures.
"""

from __future__ import annotations

import datetime as _dt
import os
import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from bristlecrawler.errors import InputError, Interrupted
from bristlecrawler.scenario.cost import Estimate
from bristlecrawler.studies import execute, store
from bristlecrawler.studies.designs import Base, Designs, expand, resolve_base
from bristlecrawler.studies.evaluate import DesignStatus
from bristlecrawler.studies.schema import Study, load_study
from bristlecrawler.studies.validate import validate_designs


@dataclass(frozen=True)
class SweepOptions:
    """out: study folder [default runs/<stamp>-sweep-<name>]; batch: FE designs of one
    structure per compiled batch (:func:`crawler.run_batch`) [default: none on a CPU, up to
    :data:`GPU_BATCH` where JAX's backend is a GPU]; scheduler: address of a
    running Dask scheduler [default: a LocalCluster]; workers: LocalCluster workers
    [default: one per core]; resume: complete the study already in ``out``; figures:
    draw them; progress: bar on stderr [default: on a terminal]; command: for meta.json;
    connect_timeout_s: how long to try to reach ``scheduler`` before giving up; note:
    called with the study's cost estimate before it starts."""

    out: Path | None = None
    scheduler: str | None = None
    workers: int | None = None
    resume: bool = False
    figures: bool = True
    progress: bool | None = None
    command: str = ""
    connect_timeout_s: float = execute.CONNECT_TIMEOUT_S
    batch: int | None = None
    note: Callable[[str], None] | None = None

    def __post_init__(self) -> None:
        from bristlecrawler.scenario.cost import WORKER_BYTES, Estimate

        if self.workers is not None and self.workers < 1:
            raise InputError(f"--workers must be >= 1, got {self.workers}")
        if self.workers is not None:
            n = self.workers
            Estimate(f"--workers {n}", n, "worker processes", 0.0, n * WORKER_BYTES).check(None)
        if self.scheduler is not None:
            execute.check_address(self.scheduler)
        if self.workers is not None and self.scheduler is not None:
            raise InputError("--workers sizes the local cluster; not with --scheduler")
        if self.batch is not None and not (isinstance(self.batch, int) and self.batch >= 1):
            raise InputError(f"--batch must be a whole number >= 1, got {self.batch!r}")
        if self.resume and self.out is None:
            raise InputError("--resume needs --out (the folder of the study to complete)")


@dataclass(frozen=True)
class Plan:
    """A validated study, ready to run."""

    study: Study
    base: Base
    designs: Designs
    resolved: dict[str, Any]
    cost: Estimate | None = None


def plan(study_ref: str, opt: SweepOptions | None = None) -> Plan:
    """Load, resolve, expand and validate a study (InputError on the first problem); its
    cost is estimated (and refused beyond what the machine holds) before the validation."""
    opt = opt or SweepOptions()
    study, folder = load_study(study_ref)
    base = resolve_base(study, folder)
    designs = expand(study, base)
    cost = estimate(study, base, designs.n, opt, designs)
    validate_designs(base, designs)
    identity = study.model_dump(mode="json", exclude={"base", "description"})
    resolved: dict[str, Any] = {"study": identity, "base_config": base.config}
    resolved = {"fingerprint": store.fingerprint(resolved)} | resolved
    resolved["study"]["description"] = study.description
    return Plan(study, base, designs, resolved, cost)


def estimate(
    study: Study, base: Base, n: int, opt: SweepOptions, designs: Designs | None = None
) -> Estimate:
    """The study's designs, CPU time, memory and disk (:mod:`scenario.cost`), checked
    against the machine; local workers are counted in, a scheduler's are not. A reduced
    study's costliest design (most bristles, cycles and samples) is checked as ``reduced``
    checks one run."""
    from bristlecrawler.scenario import cost

    workers = 0 if opt.scheduler is not None else opt.workers or os.cpu_count() or 1
    if base.model == "fe":
        from bristlecrawler.scenario.load import scenario_from_dict

        run = cost.fe_crawler(scenario_from_dict(base.config, "base"))
        design_s = run.seconds - cost.FE_COMPILE_S if run is not None else cost.FE_PAPER_RUN_S
        compile_s = cost.FE_COMPILE_S
    else:
        cfg = base.config
        closed = study.reduced_solver == "auto" and "bristles" not in study.axes
        closed &= cfg["bristles"] == 2 and cfg["history"] is None
        design_s = cost.REDUCED_CLOSED_FORM_S if closed else cost.REDUCED_EXACT_S
        if not closed:
            design_s = max(design_s, _costliest_reduced(cfg, designs).seconds)
        compile_s = 0.0
    tasks = -(-n // study.tasks_chunk)
    found = cost.study(study.name, n, tasks, design_s, workers, compile_s)
    return found.check(None, str(opt.out or "runs"))


def _costliest_reduced(cfg: dict, designs: Designs | None) -> Estimate:
    """The reduced run of the designs' largest bristle count, cycles and samples, checked
    (InputError with its estimate where one run is past what ``reduced`` runs)."""
    from bristlecrawler.scenario import cost

    def most(key: str) -> int:
        if designs is not None and key in designs.keys:
            return int(np.max(designs.values[key]))
        return int(cfg[key])

    gaits = [cfg["gait"]]
    if designs is not None and "gait" in designs.keys:
        gaits = list(np.unique(designs.values["gait"]))
    gait = "peristaltic" if "peristaltic" in gaits else gaits[0]
    run = cost.reduced_run(most("bristles"), most("cycles"), most("samples_per_cycle"), gait)
    try:
        return run.check(None, max_seconds=cost.MAX_REDUCED_S)
    except InputError as exc:
        raise InputError(f"the study's costliest design: {exc}") from None


def task_count(p: Plan, finished: set[int]) -> tuple[int, int]:
    """Tasks and designs left to run, ``finished`` tasks skipped."""
    chunk, n = p.study.tasks_chunk, p.designs.n
    total = -(-n // chunk)
    done = [t for t in finished if 0 <= t < total]
    designs = n - sum(min(chunk, n - t * chunk) for t in done)
    return total - len(done), designs


def tasks_of(p: Plan, finished: frozenset[int] | set[int] = frozenset()) -> Iterator[execute.Task]:
    """The study's tasks in order, ``chunk`` consecutive designs each, made as they are
    submitted (a study of millions of designs starts at once)."""
    chunk, n = p.study.tasks_chunk, p.designs.n
    for number, start in enumerate(range(0, n, chunk)):
        if number in finished:
            continue
        index = np.arange(start, min(start + chunk, n))
        if p.base.model == "fe":
            args = (p.base.config, [p.designs.overrides(int(i)) for i in index])
            yield execute.Task(number, index, execute.fe_task, args)
        else:
            values = {k: p.designs.values[k][index] for k in p.designs.keys}
            args = (p.base.config, values, p.study.reduced_solver)
            yield execute.Task(number, index, execute.reduced_task, args)


#: Designs per batch on a GPU by default. A batched Newton iteration of the paper crawler
#: costs about 3.4 ms + 3.7 us per design on an H200 (``bench/gpu_width.py``: 7.2 ms at
#: 1024 designs, 34 ms at 8192), so below a thousand designs the fixed part dominates.
GPU_BATCH = 1024


def _batch_size(p: Plan, batch: int | None) -> int | None:
    """The batch size: as asked (FE studies only), else batches of up to
    :data:`GPU_BATCH` designs where JAX computes on a GPU (one compiled program keeps it
    busy), else none."""
    if p.base.model != "fe":
        if batch is not None:
            raise InputError("--batch runs FE designs together; this study is of the reduced model")
        return None
    if batch is None:
        import jax

        return min(GPU_BATCH, p.designs.n) if jax.default_backend() == "gpu" else None
    return batch


def batch_tasks(p: Plan, size: int, resuming: Path | None = None) -> list[execute.Task]:
    """One task per batch of up to ``size`` designs of one structure
    (:func:`crawler.group`; InputError for a size above the number of designs); resuming
    a study folder, only its designs not done or failed, in tasks numbered after its own."""
    from bristlecrawler.crawler import group
    from bristlecrawler.scenario.convert import to_spec
    from bristlecrawler.scenario.load import scenario_from_dict
    from bristlecrawler.studies.designs import with_overrides

    overrides = [p.designs.overrides(i) for i in range(p.designs.n)]
    specs = [
        to_spec(scenario_from_dict(with_overrides(p.base.config, ov), "design")) for ov in overrides
    ]
    groups = group(specs, size)
    skip, first = set(), 0
    if resuming is not None:
        for task, part in store.read_parts(resuming):
            kept = part["status"] != DesignStatus.LOST
            skip |= {int(i) for i in part["index"][kept]}
            first = max(first, task + 1)
    out = []
    for g in groups:
        index = np.array([i for i in g if i not in skip], dtype=np.int64)
        if index.size:
            args = (p.base.config, [overrides[i] for i in index], size)
            out.append(execute.Task(first + len(out), index, execute.fe_batch_task, args))
    return out


def _default_out(name: str) -> Path:
    from bristlecrawler.io.output_paths import folder_in

    stamp = _dt.datetime.now(_dt.UTC).strftime("%Y%m%d-%H%M%S")
    path, i = folder_in("runs", f"{stamp}-sweep-{name}"), 1
    while path.exists():
        path = folder_in("runs", f"{stamp}-sweep-{name}-{i}")
        i += 1
    return path


def run_sweep(study_ref: str, options: SweepOptions | None = None) -> dict[str, Any]:
    """Run (or complete, with ``resume``) a study; returns the summary."""
    from bristlecrawler import __version__
    from bristlecrawler.io.runs import git_revision

    opt = options or SweepOptions()
    wall0 = time.perf_counter()
    p = plan(study_ref, opt)
    out = opt.out if opt.out is not None else _default_out(p.study.name)
    resuming = store.check_folder(out, p.resolved, opt.resume)
    batch = _batch_size(p, opt.batch)
    if batch is None:
        finished = store.finished_tasks(out) if resuming else set()
        ntasks, left = task_count(p, finished)
        todo = tasks_of(p, finished)
    else:
        todo = batch_tasks(p, batch, out if resuming else None)
        ntasks, left = len(todo), sum(t.index.size for t in todo)
    client = cluster = None
    try:
        if ntasks:
            client, cluster = execute.connect(opt.scheduler, opt.workers, opt.connect_timeout_s)
    except (KeyboardInterrupt, Interrupted):
        raise Interrupted(_interrupted(p, out, study_ref)) from None
    meta = {
        "package_version": __version__,
        "git_revision": git_revision(),
        "command": opt.command,
        "started_utc": _dt.datetime.now(_dt.UTC).isoformat(timespec="seconds"),
        "scheduler": opt.scheduler or f"LocalCluster({opt.workers or 'one per core'})",
        "dashboard": None if client is None else client.dashboard_link,
    }
    if opt.note is not None and p.cost.long:  # bad input is one line: said once all is checked
        opt.note(p.cost.text())
    stopped = None
    try:
        store.start_folder(out, p.resolved, meta)
        if ntasks:
            if opt.progress is not False:
                _announce(p, out, left, _workers(client))
            _run(p, out, todo, left, client, opt.progress)
    except (KeyboardInterrupt, Interrupted):
        stopped = _interrupted(p, out, study_ref)
    finally:
        try:
            execute.disconnect(client, cluster)
        except (KeyboardInterrupt, Interrupted):  # pressed again: the cluster goes anyway
            stopped = stopped or _interrupted(p, out, study_ref)
    if stopped is not None:
        raise Interrupted(stopped)
    return _finish(p, out, meta, opt, ntasks, time.perf_counter() - wall0)


def _interrupted(p: Plan, out: Path, study_ref: str) -> str:
    """The line that a sweep stopped by Ctrl-C ends with: what its folder keeps (every
    finished task's part file) and the command that completes it."""
    import shlex

    if not (out / store.STUDY_FILE).exists():
        return f"interrupted: nothing written to {out}"
    done = 0
    for _task, part in store.read_parts(out):
        done += int(np.sum(part["status"] != DesignStatus.LOST))
    again = shlex.join(["bristlecrawler", "sweep", study_ref, "--out", str(out), "--resume"])
    return (
        f"interrupted: kept {out} with {done} of {p.designs.n} designs finished; "
        f"complete it with: {again}"
    )


def _run(p: Plan, out: Path, todo, left: int, client, progress) -> None:
    from bristlecrawler.studies.progress import SweepProgress

    done_before = p.designs.n - left
    bar = SweepProgress(p.designs.n, done_before, 0, enabled=progress, workers=_workers(client))

    def on_done(task: execute.Task, result) -> None:
        store.write_part(out, task.number, task.index, result)
        failed = int(np.sum(result["status"] != DesignStatus.DONE))
        if task.index.size == 1:
            word = DesignStatus(int(result["status"][0])).name.lower()
            text = f"{p.designs.label(int(task.index[0]))} {word}"
            if failed:
                text += f": {result['error'][0]}"
            else:
                text += f" in {result['wall_time_s'][0]:.1f} s"
        else:
            n = task.index.size
            text = f"designs {task.index[0]}-{task.index[-1]}: {n - failed} done, {failed} failed"
        bar.finished(text, task.index.size, failed, list(result["wall_time_s"]))

    try:
        execute.run_tasks(client, todo, f"sweep-{p.resolved['fingerprint']}", on_done, bar.running)
    finally:
        bar.close()
    if bar.seconds:
        from bristlecrawler.io.costs import record

        measured = [s for s in bar.seconds if np.isfinite(s)]
        if measured:
            record("sweep-design", p.resolved["fingerprint"], float(np.median(measured)))


def _announce(p: Plan, out: Path, n: int, workers: int) -> None:
    """Where the study goes and how long it should take, from the median design time of
    its last run here (the designs of a study cost alike; the first of each worker also
    compiles)."""
    from bristlecrawler.io.costs import duration, recorded
    from bristlecrawler.viz.progress import announce

    before = recorded("sweep-design", p.resolved["fingerprint"])
    if before is None:
        expect = "the ETA follows from the first finished designs"
    else:
        seconds = -(-n // workers) * before.seconds
        expect = f"expected {duration(seconds)} (its last run here, {before.utc[:10]})"
    on = f"{workers} worker{'s' * (workers > 1)}"
    announce("sweep", f"{n} designs on {on} into {out}; {expect}")


def _workers(client) -> int:
    """Designs the cluster runs at once (its workers' threads)."""
    try:
        return max(sum(client.nthreads().values()), 1)
    except Exception:  # a scheduler that went away: the ETA assumes one
        return 1


#: Failed or lost designs listed one by one at the end of a sweep; beyond, a count.
LISTED_FAILURES = 20


def failures(ds, designs: Designs) -> list[dict[str, Any]]:
    """The designs that failed or were lost, in order: their number, label, status and
    one-line reason."""
    status = np.asarray(ds.status.values).ravel()
    error = np.asarray(ds.error.values).ravel()
    out = []
    for i in np.flatnonzero((status == DesignStatus.FAILED) | (status == DesignStatus.LOST)):
        out.append(
            {
                "design": int(i),
                "label": designs.label(int(i)),
                "status": DesignStatus(int(status[i])).name.lower(),
                "error": str(error[i]),
            }
        )
    return out


def _finish(p: Plan, out: Path, meta, opt: SweepOptions, ran: int, wall: float) -> dict:
    import json

    attrs = {
        "study_name": p.study.name,
        "model": p.study.model,
        "study": json.dumps(p.resolved),
        "fingerprint": p.resolved["fingerprint"],
        "package_version": meta["package_version"],
        "git_revision": meta["git_revision"],
    }
    ds = store.gather(out, p.designs, attrs)
    path = store.write_store(out, ds)
    figures = []
    if opt.figures and p.designs.n > 0:
        from bristlecrawler.studies.figures import plot_maps, plot_outputs

        folder = out / "figures"
        folder.mkdir(exist_ok=True)
        figures = plot_outputs(ds, list(p.designs.keys), folder)
        figures += plot_maps(ds, list(p.designs.keys), folder)
    status = ds.status.values
    return {
        "study": p.study.name,
        "model": p.study.model,
        "designs_total": int(status.size),
        "designs_done": int(np.sum(status == DesignStatus.DONE)),
        "designs_failed": int(np.sum(status == DesignStatus.FAILED)),
        "designs_lost": int(np.sum(status == DesignStatus.LOST)),
        "designs_pending": int(np.sum(status == DesignStatus.PENDING)),
        "failures": failures(ds, p.designs),
        "tasks_run": ran,
        "store": str(path),
        "output_dir": str(out),
        "figures": [str(f) for f in figures],
        "wall_time_s": wall,
    }
