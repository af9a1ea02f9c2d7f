"""Designs of one structure run side by side in one compiled program.

:func:`run_batch` takes designs that differ only in values (see :mod:`.structure`): the
gravity step of every design, then its stroke, are stepped by one compiled loop vmapped
over the designs (a :class:`fe.Stepper` with the batch loop); between them each design gets its
damping from its own modal analysis (:class:`ModalDamping`, short, on the host). Every
design keeps its own step size, rejections, Newton iterations and records, and the same
chunks of simulated time as :func:`run` takes, so a design of a batch takes the steps of
its single run (to round-off). A design that fails is reported with the message its
single run would raise; the others go on.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import jax
import jax.numpy as jnp
import numpy as np

from bristlecrawler import fe
from bristlecrawler.crawler.history import CrawlerHistory
from bristlecrawler.crawler.model import build
from bristlecrawler.crawler.runner import (
    DEFAULT_STAGES,
    ModalDamping,
    Progress,
    Rig,
    RunContext,
    RunOptions,
    Settle,
    SteppedStage,
    history_of,
)
from bristlecrawler.crawler.spec import CrawlerSpec
from bristlecrawler.crawler.structure import check_one_structure, differences, structure_key
from bristlecrawler.errors import BristlecrawlerError, InputError


@dataclass(frozen=True)
class BatchResult:
    """The outcome of :func:`run_batch`, one entry per design in the order given.

    Attributes:
        histories: each design's :class:`CrawlerHistory`, or None where it failed.
        errors: None, or the one-line reason a design failed.
        stats: of the batch: ``width`` (designs in the compiled program), ``compile_time_s``
            (compilation or cache load in this call of the batched program and of the
            programs each design calls on its own; 0 for a program this process had
            already), ``stroke_wall_time_s``, ``wall_time_s``,
            ``prepare_wall_time_s`` (building the designs and their initial states),
            ``settle_wall_time_s`` (the batched gravity step), ``modal_wall_time_s``
            (the designs' modal analyses), ``histories_wall_time_s`` (their records
            made into histories), compilation left out of each,
            ``batch_iterations`` (iterations of the batched loop: one Newton iteration
            of every design in each), ``design_iterations`` (the designs' own stroke
            iterations, summed) and ``utilisation`` = design_iterations / (width x
            batch_iterations).
    """

    histories: tuple[CrawlerHistory | None, ...]
    errors: tuple[str | None, ...]
    stats: dict = field(default_factory=dict)


def run_batch(
    specs: Sequence[CrawlerSpec],
    *,
    width: int | None = None,
    stages: Sequence[SteppedStage] = DEFAULT_STAGES,
    options: RunOptions | None = None,
    on_progress: Callable[[Progress], None] | None = None,
) -> BatchResult:
    """Run designs of one structure as one batch, through the ``stages`` a single run
    takes (default: gravity step, modal damping, stroke).

    ``width``: designs in the compiled program (default: as many as given); a batch of
    fewer designs is padded with masked copies, so that the batches of a sweep share one
    program. Each stage is a :class:`SteppedStage`: every design's ``start``, then the
    stepping of all of them in one batched program, then every design's ``finish``. Bad
    input (no designs, designs of different structures, more designs than ``width``, a
    stage a batch cannot run) is an :class:`InputError` before any work; a design that
    fails in a stage gets its error in :attr:`BatchResult.errors`.
    """
    wall0 = time.perf_counter()
    specs = tuple(specs)
    width = check_designs(specs, width)
    rigs = [build(s) for s in specs]
    built = time.perf_counter()
    ctxs, errors, stats = run_rigs(rigs, stages, width, options, on_progress)
    for ctx, err in zip(ctxs, errors, strict=True):
        if err is None:  # a design's wall time counts its building, as a single run's
            ctx.stats["wall_time_s"] += built - wall0
    histories = []
    t_records = time.perf_counter()
    for ctx, err in zip(ctxs, errors, strict=True):
        histories.append(None if err is not None else history_of(ctx))
    stats["histories_wall_time_s"] = time.perf_counter() - t_records
    stats["wall_time_s"] = time.perf_counter() - wall0
    stats["prepare_wall_time_s"] += built - wall0
    return BatchResult(tuple(histories), tuple(errors), stats)


def run_rigs(
    rigs: Sequence[Rig],
    stages: Sequence[SteppedStage],
    width: int,
    options: RunOptions | None = None,
    on_progress: Callable[[Progress], None] | None = None,
) -> tuple[list[RunContext], list[str | None], dict]:
    """``stages`` on built rigs of one structure (crawlers or drag tests' rigs) as one
    batch of ``width`` designs: (each design's run context, its error or None, the
    batch's statistics as in :class:`BatchResult` but for ``wall_time_s`` and
    ``histories_wall_time_s``, which are the caller's)."""
    if not 1 <= len(rigs) <= width:
        raise InputError(f"a batch of width {width} holds 1 to {width} designs, got {len(rigs)}")
    wall0 = time.perf_counter()
    stages = _check_stages(stages)
    options = options or RunOptions()
    ctxs = [RunContext(r, options, None, t_end=0.0, batched=True) for r in rigs]
    for ctx in ctxs:
        ctx.stages = stages
    _check_programs(ctxs)
    errors: list[str | None] = [None] * len(ctxs)
    batch = _BatchAdvance(ctxs, errors, width, on_progress)
    stats = {"width": width, "compile_time_s": 0.0, "prepare_wall_time_s": 0.0}
    stats |= {"stroke_wall_time_s": 0.0, "batch_iterations": 0, "design_iterations": 0}
    stats["utilisation"] = np.nan
    built = time.perf_counter()
    for stage in stages:
        _add_stats(stats, stage, _run_stage(stage, batch))
    stats["prepare_wall_time_s"] += built - wall0
    for ctx, err in zip(ctxs, errors, strict=True):
        if err is None:
            ctx.stats["wall_time_s"] = time.perf_counter() - wall0
            ctx.stats["compile_time_s"] = stats["compile_time_s"]
    return ctxs, errors, stats


def _run_stage(stage: SteppedStage, batch: _BatchAdvance) -> dict:
    """``stage`` for every live design of ``batch``: the designs' starts, their stepping
    in one batched program, their finishes. Returns the stage's times (s): ``starts``,
    ``compiling`` (in the starts), ``whole``, and the batched stepping's statistics."""
    ctxs, errors = batch.ctxs, batch.errors
    t0, compiling = time.perf_counter(), 0.0
    for i, ctx in enumerate(ctxs):
        if errors[i] is None:
            before = ctx.stats.get("compile_time_s", 0.0)
            _guarded(errors, i, lambda ctx=ctx: stage.start(ctx))
            seconds = ctx.stats.get("compile_time_s", 0.0) - before
            compiling += seconds if math.isfinite(seconds) else 0.0
    starts = time.perf_counter() - t0
    live = [i for i, e in enumerate(errors) if e is None]
    plans = {i: stage.stepping(ctxs[i]) for i in live}
    stepped = {"wall_time_s": 0.0, "compile_time_s": 0.0}
    if live and all(p is not None for p in plans.values()):
        stepped = batch.run(stage, plans)
    for i, ctx in enumerate(ctxs):
        if errors[i] is None:
            _guarded(errors, i, lambda ctx=ctx: stage.finish(ctx))
    whole = time.perf_counter() - t0
    return {"starts": starts, "compiling": compiling, "whole": whole, "stepped": stepped}


def _add_stats(stats: dict, stage: SteppedStage, times: dict) -> None:
    """The batch's statistics (see :class:`BatchResult`) with a stage's ``times``."""
    stepped = times["stepped"]
    stats["compile_time_s"] += times["compiling"] + stepped["compile_time_s"]
    if isinstance(stage, Settle):
        stats["prepare_wall_time_s"] += times["starts"] - times["compiling"]
        stats["settle_wall_time_s"] = stepped["wall_time_s"] - stepped["compile_time_s"]
    elif isinstance(stage, ModalDamping):
        stats["modal_wall_time_s"] = times["whole"]
    elif stage.measured:
        for key in ("stroke_wall_time_s", "batch_iterations", "design_iterations"):
            stats[key] = stepped[key]
        stats["utilisation"] = stepped["utilisation"]


def _guarded(errors, i, work):
    """``work()``, or None with its error as design ``i``'s."""
    try:
        return work()
    except BristlecrawlerError as exc:
        errors[i] = f"{exc}"
        return None


def _check_stages(stages) -> tuple:
    stages = tuple(stages)
    for st in stages:
        if not isinstance(st, SteppedStage):
            raise InputError(
                f"a batch runs stages that step in time as SteppedStage objects (start, "
                f"stepping, finish); {type(st).__name__} is not one"
            )
    return stages


def group(specs: Sequence[CrawlerSpec], size: int) -> list[list[int]]:
    """Indices of ``specs`` in batches of at most ``size`` designs of one structure (in
    the order of their first design); :class:`InputError` for no designs or a ``size``
    that is not a whole number in [1, number of designs]."""
    specs = tuple(specs)
    if not specs:
        raise InputError("a batch needs at least one design, got none")
    if not (isinstance(size, int) and not isinstance(size, bool) and size >= 1):
        raise InputError(f"the batch size must be a whole number >= 1, got {size!r}")
    if size > len(specs):
        raise InputError(f"batch size {size} is larger than the {len(specs)} designs given")
    by_structure: dict[str, list[int]] = {}
    for i, spec in enumerate(specs):
        by_structure.setdefault(structure_key(spec), []).append(i)
    return [ix[k : k + size] for ix in by_structure.values() for k in range(0, len(ix), size)]


def check_designs(specs, width) -> int:
    """The width of a batch of ``specs`` (default: as many as given), or an
    :class:`InputError` (no designs, not CrawlerSpec objects, more designs than ``width``,
    designs of different structures)."""
    if not specs:
        raise InputError("a batch needs at least one design, got none")
    if not all(isinstance(s, CrawlerSpec) for s in specs):
        raise InputError("the designs of a batch are CrawlerSpec objects")
    if width is None:
        width = len(specs)
    if not (isinstance(width, int) and not isinstance(width, bool) and width >= 1):
        raise InputError(f"the batch width must be a whole number >= 1, got {width!r}")
    if len(specs) > width:
        raise InputError(
            f"a batch of width {width} holds at most {width} designs, got {len(specs)}"
        )
    check_one_structure(specs)
    return width


def _check_programs(ctxs) -> None:
    """The built programs must match too (a structure the spec keys do not show, such as
    the corner contact's window, which follows the substrate's period)."""
    first = ctxs[0]
    stepper = first.stepper(True, "batch")
    tree = jax.tree.structure(first.crawler.model.params)
    shapes = [np.shape(x) for x in jax.tree.leaves(first.crawler.model.params)]
    for i, ctx in enumerate(ctxs[1:], start=1):
        params = ctx.crawler.model.params
        same = (
            ctx.stepper(True, "batch") == stepper
            and jax.tree.structure(params) == tree
            and [np.shape(x) for x in jax.tree.leaves(params)] == shapes
        )
        if not same:
            keys = ", ".join(k for k, _, _ in differences(first.spec, ctx.spec)) or "none"
            raise InputError(
                "the designs of a batch must share one structure: designs 0 and "
                f"{i} compile to different programs (keys that differ: {keys})"
            )


#: Batched programs compiled in this process, by static arguments and argument types.
_COMPILED: dict = {}


def _strong(tree):
    """Arrays of fixed (not weak) types, the signature of the compiled program."""
    return jax.tree.map(lambda x: jnp.asarray(x, dtype=jnp.result_type(x)), tree)


def _compiled(run, args):
    """(The batched program compiled for ``args``, seconds spent compiling it now)."""
    key = (run, jax.tree.structure(args), tuple((x.shape, x.dtype) for x in jax.tree.leaves(args)))
    if key in _COMPILED:
        return _COMPILED[key], 0.0
    t0 = time.perf_counter()
    _COMPILED[key] = run.lower(*args).compile()
    return _COMPILED[key], time.perf_counter() - t0


class _BatchAdvance:
    """The stepping of a stage for every live design (one that has not failed), in one
    batched program, as each design's :class:`Advance` asks: its span, in the chunks of
    simulated time its single run takes (the chunk ends cap the step, so other chunks
    would give other steps), with or without the energy check. The compiled loop starts
    a design's next chunk itself, and returns to the host only when a design's record
    buffer is full or every design is done. Every stage runs one program: the check is
    switched per call, not compiled in or out."""

    def __init__(self, ctxs, errors, width, on_progress):
        self.ctxs, self.errors, self.width = ctxs, errors, width
        self.on_progress = on_progress

    def run(self, stage, plans: dict) -> dict:
        """Step every live design as ``plans`` (design -> :class:`Advance`) asks."""
        t0 = time.perf_counter()
        stats = {"width": self.width, "compile_time_s": 0.0, "stroke_wall_time_s": 0.0}
        stats |= {"batch_iterations": 0, "design_iterations": 0, "utilisation": np.nan}
        self.live = [i for i, e in enumerate(self.errors) if e is None]
        checks = {p.check for p in plans.values()}
        if len(checks) > 1:
            raise InputError(f"{stage.name}: the designs of a batch step with one energy check")
        if self.live:
            self._run(stage, plans, checks.pop(), stats)
        stats["wall_time_s"] = time.perf_counter() - t0
        return stats

    def _inputs(self, plans, slots, real):
        ctxs = self.ctxs
        dt_min = np.array([ctxs[i].spec.solver.dt_min for i in slots])
        dt_max = np.array([plans[i].dt_max for i in slots])
        t = np.array([float(ctxs[i].state.t) for i in slots])
        t_end = np.where(real, t + np.array([plans[i].span for i in slots]), t)
        chunk = np.array([plans[i].chunk for i in slots])
        return t, t_end, chunk, dt_min, dt_max

    def _run(self, stage, plans: dict, check: bool, stats: dict) -> None:
        ctxs, live = self.ctxs, self.live
        # Padding slots repeat a live design and stay masked (their stage is empty).
        slots = live + [live[-1]] * (self.width - len(live))
        real = np.array([j < len(live) for j in range(self.width)])
        first = ctxs[live[0]]
        stepper = first.stepper(True, "batch")
        params = fe.stack([ctxs[i].model.params for i in slots])
        carry, pending = stepper.start(
            [ctxs[i].state for i in slots], [ctxs[i].dt for i in slots], params
        )
        t, t_end, chunk, dt_min, dt_max = self._inputs(plans, slots, real)
        t_stop = np.minimum(t + chunk, t_end)
        checked = np.full(self.width, check)
        active = real.copy()
        wall0, n_batch = time.perf_counter(), 0
        while active.any():
            args = (carry, pending, params, t_stop, t_end, chunk, dt_min, dt_max, checked)
            args = _strong(args)
            program, seconds = _compiled(stepper.program, args)
            stats["compile_time_s"] += seconds
            carry, pending, buf, k, failed, t_stop, n = program(*args)
            buf, k, failed, t_stop = jax.device_get((buf, k, failed, t_stop))
            n_batch += int(n)
            t = np.asarray(carry.state.t)
            for j in np.flatnonzero(active):
                ctx = ctxs[slots[j]]
                # Every stage records, as a single run does (the gravity step's records
                # number a failure's step; the stage clears them when it finishes).
                ctx.records.extend(jax.tree.map(lambda b, j=j: b[j], buf), k[j])
                if failed[j]:
                    self._fail(slots[j], stage, jax.tree.map(lambda x, j=j: x[j], carry))
                    active[j] = False
                elif t[j] >= t_end[j] - 1e-9:
                    active[j] = False
            t_stop = np.where(active, t_stop, t)
            self._report(stage, t, t_end, active)
        wall = time.perf_counter() - wall0
        its, rej = np.asarray(carry.iterations), np.asarray(carry.rejected)
        for j in np.flatnonzero(real):
            ctx = ctxs[slots[j]]
            if self.errors[slots[j]] is None:
                ctx.state = jax.tree.map(lambda x, j=j: x[j], carry.state)
            ctx.dt = float(carry.dt[j])
            ctx.iterations += int(its[j])
            ctx.rejected += int(rej[j])
            if check:
                ctx.stats["batch_width"] = self.width
        own = int(its[real].sum())
        stats |= {"stroke_wall_time_s": wall, "batch_iterations": n_batch}
        stats |= {"design_iterations": own, "utilisation": own / max(self.width * n_batch, 1)}

    def _fail(self, i, stage, carry) -> None:
        ctx = self.ctxs[i]
        ctx.state = carry.state
        where = f"{stage.name} near t = {float(carry.state.t):.4g} s: "
        self.errors[i] = where + ctx.why(carry)

    def _report(self, stage, t, t_end, active) -> None:
        if self.on_progress is None:
            return
        done = sum(max(len(self.ctxs[i].records) - 1, 0) for i in self.live)
        its = sum(self.ctxs[i].iterations for i in self.live)
        now = float(t[active].min()) if active.any() else float(t_end.max())
        self.on_progress(Progress(stage.name, now, float(t_end.max()), done, its))
