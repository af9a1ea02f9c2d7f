"""Running a built crawler as a sequence of stages (paper Section 3's analysis steps).

The default stages are the paper's: :class:`Settle` (step 1, gravity, with provisional
mass-proportional damping), :class:`ModalDamping` (the first resonant frequency of the
settled crawler, contact tangent included, and the Rayleigh damping set to the ratio there)
and :class:`Stroke` (step 2, the prescribed shortening, HHT-alpha with adaptive steps).
Every accepted step of the stroke is recorded (:mod:`.record`) and the run returns a
:class:`CrawlerHistory`. Progress goes to a callback, so a script passes nothing, the CLI
a progress bar and a sweep worker its own.

Step control: a step is cut when Newton fails, when a node turns too far or a contact
point goes too deep (:class:`fe.Integrator`), and when the step's energy balance
(:class:`EnergyCheck`) shows energy created beyond ``solver.energy_tol`` or, in the
stroke, lost beyond ``solver.energy_loss_tol``.
"""

from __future__ import annotations

import dataclasses
import math
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Protocol

import jax
import numpy as np

from bristlecrawler import fe
from bristlecrawler.crawler.history import CrawlerHistory
from bristlecrawler.crawler.model import CrawlerModel, build
from bristlecrawler.crawler.record import EnergyCheck, Records
from bristlecrawler.crawler.spec import CrawlerSpec
from bristlecrawler.crawler.warm import compile_programs
from bristlecrawler.errors import InputError, SolverError
from bristlecrawler.fe.status import CONTACT_OVERFLOW, STEP_ERROR, describe, is_fatal


@dataclass(frozen=True)
class RunOptions:
    """How a run is driven (what is not part of the design).

    Attributes:
        dt0: first time step, s.
        settle_omega: first-frequency estimate for the settle's provisional damping, rad/s
            (replaced by the modal analysis after it).
        capacity: steps per compiled chunk.
        driver: "host" (the :class:`fe.Stepper`'s loop in Python), "compiled" (one XLA
            loop) or "auto" (host on a CPU, compiled
            elsewhere: on a CPU both take the same time per run, but the compiled loop
            takes longer to compile and to load from the cache).
        compile_threads: threads that compile the run's programs at its start (1: one
            after the other; XLA compiles outside Python's lock, so more threads use more
            cores).
        batch_trials: how a batch's Newton line search makes its trials (the same
            results either way): "sequential" (one residual per trial, as a single run:
            under ``vmap`` every design pays the batch's longest search), "parallel"
            (all of them in one vectorised residual) or "auto" (sequential on a CPU,
            which computes every trial's arithmetic, parallel elsewhere, where a
            batched iteration's cost is mostly the number of operations launched).
            Single runs always search sequentially.
    """

    dt0: float = 1e-3
    settle_omega: float = 200.0
    capacity: int = 512
    driver: str = "auto"
    compile_threads: int = 4
    batch_trials: str = "auto"

    def __post_init__(self) -> None:
        if self.driver not in ("auto", "host", "compiled"):
            raise InputError(f"driver must be 'auto', 'host' or 'compiled', got {self.driver!r}")
        if self.batch_trials not in ("auto", "sequential", "parallel"):
            raise InputError(
                "batch_trials must be 'auto', 'sequential' or 'parallel', "
                f"got {self.batch_trials!r}"
            )
        if not (isinstance(self.compile_threads, int) and self.compile_threads >= 1):
            raise InputError(
                f"compile_threads must be a whole number >= 1, got {self.compile_threads!r}"
            )


@dataclass(frozen=True)
class Progress:
    """What a progress callback gets: the stage, the simulated time ``t`` out of ``t_end``
    (s, from the start of the run), accepted steps and Newton iterations so far."""

    stage: str
    t: float
    t_end: float
    steps: int
    iterations: int


class Stage(Protocol):
    """A stage of a run: ``span(ctx)`` simulated seconds it adds (for progress), and
    ``__call__(ctx)`` does its work on the run's state.

    A stage that a batch can run too (:func:`run_batch`) is a :class:`SteppedStage`:
    its work is ``start(ctx)``, then the time stepping ``stepping(ctx)`` asks for, then
    ``finish(ctx)``; a single run does the three in turn, a batch does each design's
    start, steps every design at once, then does each design's finish."""

    name: str

    def span(self, ctx: RunContext) -> float: ...

    def __call__(self, ctx: RunContext) -> None: ...


@dataclass(frozen=True)
class Advance:
    """The time stepping a stage asks for: ``span`` s from the state's time, in chunks
    of ``chunk`` s (a chunk's end caps a step, so a batch takes the same chunks as the
    single run), steps of at most ``dt_max`` s; ``check``: the whole energy check, or
    (False) its bound on the energy created alone (:meth:`RunContext.energy_check`)."""

    span: float
    chunk: float
    dt_max: float
    check: bool


class SteppedStage:
    """Base of the stages that step in time: ``start``, the ``stepping`` they ask for
    (None: no stepping), ``finish``. Calling one does the three in turn. ``measured``:
    the stage whose stepping a batch's stroke statistics time (the stroke, a drag)."""

    name: str = ""
    measured = False

    def span(self, ctx: RunContext) -> float:
        return 0.0

    def start(self, ctx: RunContext) -> None:
        """What the stage does before it steps."""

    def stepping(self, ctx: RunContext) -> Advance | None:
        return None

    def finish(self, ctx: RunContext) -> None:
        """What the stage does after it has stepped."""

    def __call__(self, ctx: RunContext) -> None:
        self.start(ctx)
        plan = self.stepping(ctx)
        if plan is not None:
            t = float(ctx.state.t)
            t_end = t + plan.span
            while t < t_end - 1e-9:
                ctx.advance(min(t + plan.chunk, t_end), plan.dt_max, self.name, plan.check)
                t = float(ctx.state.t)
        self.finish(ctx)


class Rig(Protocol):
    """What a run steps: the crawler (:class:`CrawlerModel`) or a drag test's rig
    (:class:`~.drag.DragModel`). ``model`` the FE model, ``spec`` the design (its damping,
    actuation, solver and contact settings drive the stages), ``body`` the nodes whose
    speed at the end of the gravity step tells how settled the run starts, and
    ``observer()`` the jitted record of each accepted step."""

    model: object
    spec: CrawlerSpec

    @property
    def body(self) -> tuple[int, ...]: ...

    def observer(self): ...


@dataclass
class RunContext:
    """The state a run's stages share: the :class:`Rig` (the crawler or a drag test's
    rig), its current FE
    model (with the damping in force), dynamic state, step size, records, counters, the
    run's ``stages`` (so that the first one can compile what the others need), whether it
    is a design of a batch, and the marks a stage leaves for its own ``finish``."""

    crawler: Rig
    options: RunOptions
    on_progress: Callable[[Progress], None] | None
    t_end: float
    model: object = None
    state: object = None
    dt: float = 0.0
    damping: object = None
    omega1: float = math.nan
    records: Records = field(default_factory=Records)
    iterations: int = 0
    rejected: int = 0
    stats: dict = field(default_factory=dict)
    stage: str = ""
    stages: tuple = ()
    batched: bool = False
    marks: dict = field(default_factory=dict)

    @property
    def spec(self) -> CrawlerSpec:
        return self.crawler.spec

    @property
    def host(self) -> bool:
        o = self.options.driver
        return o == "host" or (o == "auto" and jax.default_backend() == "cpu")

    @property
    def parallel_trials(self) -> bool:
        """Whether a batch of this crawler makes its line-search trials at once."""
        o = self.options.batch_trials
        return o == "parallel" or (o == "auto" and jax.default_backend() != "cpu")

    def report(self, stage: str | None = None) -> None:
        if stage is not None:
            self.stage = stage
        if self.on_progress is not None:
            t = float(self.state.t) if self.state is not None else 0.0
            self.on_progress(
                Progress(self.stage, t, self.t_end, max(len(self.records) - 1, 0), self.iterations)
            )

    def stepper(self, check: bool, loop: str | None = None):
        """The :class:`fe.Stepper` of this crawler (topology, terms, integrator, observer,
        capacity, step control, energy check; ``loop`` this run's, or "batch"): equal for
        designs that share one compiled program."""
        sv = self.spec.solver
        m = self.crawler.model
        loop = loop or ("host" if self.host else "compiled")
        return fe.Stepper(
            m.topology,
            m.terms,
            sv.integrator(self.spec.contact.penetration_limit),
            fe.SaveAt(self.crawler.observer(), self.options.capacity),
            sv.control,
            self.energy_check(losses=check),
            loop=loop,
            parallel_trials=loop == "batch" and self.parallel_trials,
        )

    def energy_check(self, losses: bool) -> EnergyCheck | None:
        """The steps' energy check: energy created beyond ``solver.energy_tol`` is refused
        in every stage (in the gravity step it keeps Newton off the roots that curl a steep
        bristle off the substrate, docs/findings.md), energy lost beyond
        ``solver.energy_loss_tol`` only where ``losses`` (the stroke, the drag)."""
        sv = self.spec.solver
        tols = (sv.energy_tol, sv.energy_loss_tol if losses else math.inf)
        return EnergyCheck(*tols) if any(map(math.isfinite, tols)) else None

    def advance(self, t_stop: float, dt_max: float, where: str, check: bool) -> None:
        """Drive to ``t_stop``; every accepted step's record goes to ``records``."""
        stepper = self.stepper(check)
        carry = stepper.start(self.state, self.dt)
        while float(carry.state.t) < t_stop - 1e-9:
            it0, rej0 = int(carry.iterations), int(carry.rejected)
            carry, buf, k, failed = stepper.run(
                carry, self.model.params, t_stop, self.spec.solver.dt_min, dt_max
            )
            buf, k = jax.device_get(buf), int(k)
            self.records.extend(buf, k)
            self.iterations += int(carry.iterations) - it0
            self.rejected += int(carry.rejected) - rej0
            self.state, self.dt = carry.state, float(carry.dt)
            if bool(failed):
                raise SolverError(
                    f"{where} near t = {float(carry.state.t):.4g} s: " + self.why(carry)
                )
            self.report()

    def why(self, carry) -> str:
        """Why the drivers' ``carry`` stopped: the step's message, and the cause."""
        sv = self.spec.solver
        cause = int(carry.cause)
        msg = fe.message(carry.info, f"step {len(self.records)}")
        if cause == CONTACT_OVERFLOW:
            return msg + f" (contact.active_points = {self.spec.contact.active_points})"
        if is_fatal(cause):  # stopped at once: dt was not cut
            return msg
        text = describe(cause)
        if cause == STEP_ERROR:
            text += (
                f": it created more energy than solver.energy_tol = {sv.energy_tol:g} mJ or "
                f"lost more than solver.energy_loss_tol = {sv.energy_loss_tol:g} mJ"
            )
        return msg + f"; dt cut below dt_min = {sv.dt_min:g} s (last attempt: {text})"


@dataclass(frozen=True)
class Settle(SteppedStage):
    """Step 1: the crawler settles under gravity from its reference state for
    ``actuation.settle_time`` (the actuators start after it), with provisional
    mass-proportional damping (ratio ``max(damping.ratio, 0.15)`` at
    ``RunOptions.settle_omega``)."""

    name: str = "gravity step"

    def span(self, ctx: RunContext) -> float:
        return ctx.spec.actuation.settle_time

    def start(self, ctx: RunContext) -> None:
        self.setup(ctx)
        ctx.report("compiling")
        ctx.state = _prepare(ctx)
        ctx.report(self.name)

    def stepping(self, ctx: RunContext) -> Advance:
        span = self.span(ctx) - float(ctx.state.t)
        return Advance(span, span, self.dt_max(ctx), check=False)

    def finish(self, ctx: RunContext) -> None:
        ctx.records.clear()
        body = ctx.crawler.body
        if body:
            # How far from rest the stroke starts (docs/findings.md); mass-proportional
            # damping a0 takes every mode down at the rate a0 / 2, so 2 v / a0 is the
            # distance the body would still go, to its order of magnitude.
            v = jax.device_get(ctx.state.v)[list(body), :2]
            speed = float(np.max(np.hypot(v[:, 0], v[:, 1])))
            ctx.stats["settle_speed_mm_s"] = speed
            a0 = float(ctx.damping.a0)
            ctx.stats["settle_creep_mm"] = 2.0 * speed / a0 if a0 > 0.0 else math.inf

    @staticmethod
    def setup(ctx: RunContext) -> None:
        """The provisional damping (and the model with it) and the first step size."""
        ratio, omega = max(ctx.spec.damping.ratio, 0.15), ctx.options.settle_omega
        ctx.damping = fe.Rayleigh.from_ratio(ratio, omega, "mass")
        ctx.model = ctx.damping.apply(ctx.crawler.model)
        ctx.dt = ctx.options.dt0

    @staticmethod
    def dt_max(ctx: RunContext) -> float:
        """The largest step of the gravity step (s)."""
        return min(ctx.spec.solver.dt_max, 0.01)


def _prepare(ctx: RunContext):
    """The run's initial state, with the programs of its stages compiled (or loaded from
    the persistent cache) at once by :func:`compile_programs` when the run uses the host
    loop (the compiled loop is one program: nothing to compile beside it) or runs in a
    batch. The wall time goes to ``stats["compile_time_s"]``."""
    if not (ctx.host or ctx.batched):
        ctx.stats["compile_time_s"] = math.nan
        return fe.initial_state(ctx.model)
    modal = any(isinstance(s, ModalDamping) for s in ctx.stages)
    # A batch steps with its own program: its designs compile only what each calls alone.
    step = not ctx.batched
    state, ctx.stats["compile_time_s"] = compile_programs(ctx, step=step, modal=modal)
    return state


@dataclass(frozen=True)
class ModalDamping(SteppedStage):
    """The Rayleigh damping of the stroke: ``damping.ratio`` at the first resonant
    frequency of the settled crawler (modal analysis with the contact tangent), or the
    explicit ``a0``, ``a1``."""

    name: str = "modal analysis"

    def start(self, ctx: RunContext) -> None:
        ctx.report(self.name)
        d, state = ctx.spec.damping, ctx.state
        modes = fe.modes(ctx.model, state.q, n_modes=1, t=float(state.t), history=state.history)
        ctx.omega1 = float(modes.omega[0])
        if d.kind == "explicit":
            ctx.damping = fe.Rayleigh(d.a0, d.a1)
        else:
            _check_resonance(ctx, float(modes.eigenvalues[0]))
            ctx.damping = fe.Rayleigh.from_ratio(d.ratio, ctx.omega1, d.kind)
        ctx.model = ctx.damping.apply(ctx.crawler.model)


def _check_resonance(ctx: RunContext, w2: float) -> None:
    zero = 1e-6 * ctx.options.settle_omega  # rad/s: below it the lowest mode does not resonate
    if ctx.omega1 > zero:
        return
    if w2 < -(zero**2):
        why = (
            f"the settled state is unstable (lowest eigenvalue of the tangent {w2:.3g} "
            "rad^2/s^2: the crawler rocks on its contact points)"
        )
    else:
        why = "the crawler has a free rigid-body mode (no bristle sticks)"
    raise SolverError(
        f"after the gravity step {why} at t = {float(ctx.state.t):.3g} s, so the damping "
        "cannot be set at the first resonance; lengthen actuation.settle_time or give "
        "damping a0/a1"
    )


@dataclass(frozen=True)
class Stroke(SteppedStage):
    """Step 2: the prescribed shortening of every segment, recorded step by step, in
    chunks of ``chunk`` simulated seconds (None: a twentieth of a period, at least 0.5 s)
    so that progress moves."""

    chunk: float | None = None
    name: str = "stroke"
    measured = True

    def span(self, ctx: RunContext) -> float:
        return ctx.spec.actuation.stroke_duration(ctx.spec.segments)

    def start(self, ctx: RunContext) -> None:
        ctx.report("")
        ctx.records.append(jax.device_get(ctx.crawler.observer()(ctx.state, ctx.model.params)))
        ctx.marks["stroke"] = (time.perf_counter(), ctx.iterations)

    def stepping(self, ctx: RunContext) -> Advance:
        chunk = self.chunk or max(ctx.spec.actuation.period / 20.0, 0.5)
        return Advance(self.span(ctx), chunk, ctx.spec.solver.dt_max, check=True)

    def finish(self, ctx: RunContext) -> None:
        wall0, it0 = ctx.marks.pop("stroke")
        ctx.stats["stroke_wall_time_s"] = time.perf_counter() - wall0
        ctx.stats["stroke_newton_iterations"] = ctx.iterations - it0


@dataclass(frozen=True)
class Hold(SteppedStage):
    """Keep recording for ``duration`` s after the stroke with the actuators at rest (the
    crawler settles; a user stage of the simplest kind)."""

    duration: float
    name: str = "hold"

    def span(self, ctx: RunContext) -> float:
        return self.duration

    def start(self, ctx: RunContext) -> None:
        if not (math.isfinite(self.duration) and self.duration > 0):
            raise InputError(f"Hold duration must be a positive number of s, got {self.duration}")
        if not ctx.records:
            raise InputError("Hold records after the stroke: put it after Stroke()")
        ctx.report(self.name)

    def stepping(self, ctx: RunContext) -> Advance:
        return Advance(self.duration, self.duration, ctx.spec.solver.dt_max, check=True)


DEFAULT_STAGES: tuple[Stage, ...] = (Settle(), ModalDamping(), Stroke())


def run(
    crawler: CrawlerModel | CrawlerSpec,
    stages: Sequence[Stage] = DEFAULT_STAGES,
    *,
    options: RunOptions | None = None,
    on_progress: Callable[[Progress], None] | None = None,
) -> CrawlerHistory:
    """Run ``stages`` on a built crawler (or build a spec first) and return the record of
    its stroke; raises :class:`SolverError` with where and why on a solver failure."""
    cm = crawler if isinstance(crawler, CrawlerModel) else build(crawler)
    ctx = run_stages(cm, stages, options, on_progress)
    if not ctx.records:
        raise InputError("a run needs a recording stage (Stroke) after the others")
    return history_of(ctx)


def run_stages(crawler, stages: Sequence[Stage], options=None, on_progress=None) -> RunContext:
    """Run ``stages`` in order on ``crawler`` (a :class:`CrawlerModel`, or any object
    :class:`RunContext` takes) and return their context; ``stats["wall_time_s"]`` is
    the whole."""
    wall0 = time.perf_counter()
    ctx = RunContext(crawler, options or RunOptions(), on_progress, t_end=0.0)
    ctx.stages = tuple(stages)
    ctx.t_end = sum(s.span(ctx) for s in stages)
    for stage in stages:
        stage(ctx)
    ctx.stats["wall_time_s"] = time.perf_counter() - wall0
    return ctx


#: The attributes of a :class:`CrawlerHistory`.
_HISTORY_FIELDS = frozenset(f.name for f in dataclasses.fields(CrawlerHistory))


def history_of(ctx: RunContext) -> CrawlerHistory:
    """The :class:`CrawlerHistory` of a ctx's records (times from the stroke's start): its
    series are the declared quantities (:mod:`.quantities`), computed from the records."""
    from bristlecrawler.crawler.quantities import RunRecords, history_fields

    spec, a = ctx.spec, ctx.spec.actuation
    stats = {
        "steps": len(ctx.records) - 1,
        "newton_iterations": ctx.iterations,
        "rejected_steps": ctx.rejected,
        "first_frequency_hz": ctx.omega1 / (2 * math.pi),
        "rayleigh_a0": ctx.damping.a0,
        "rayleigh_a1": ctx.damping.a1,
        **ctx.stats,
    }
    return CrawlerHistory(
        **history_fields(RunRecords(ctx.records, ctx.crawler, spec), _HISTORY_FIELDS),
        period=a.period if a.history is None else None,
        cycles=a.cycles,
        stats=stats,
        name=spec.name,
    )
