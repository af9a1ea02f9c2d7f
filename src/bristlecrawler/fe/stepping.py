"""One door to time stepping: a :class:`Stepper` says what a run steps and how, and runs it.

A stepper is a value (frozen, hashable, compared by its settings): the structure
(``topology``, ``terms``), the scheme (:class:`~.integrator.Integrator`), what to record
after each accepted step (:class:`SaveAt`), the adaptive step rule
(:class:`~.control.StepControl`), an optional ``check`` of each converged step, and the
loop that takes the steps:

* ``"host"``: a Python loop around the compiled step (the smaller program to compile; on
  a CPU as fast per run as the compiled loop);
* ``"compiled"``: one XLA loop (no host round trip per step; the form for a GPU);
* ``"batch"``: one XLA loop over designs of one structure stacked on a leading axis, one
  Newton iteration of every design at a time, each at its own point of its own step.

Every loop takes the same steps (halve on failure, grow after easy steps, stay within
[dt_min, dt_max]; :meth:`StepControl.decide`) and records the same rows. Use it as

* :meth:`Stepper.solve` (or :func:`solve`): a whole run, records gathered;
* :meth:`Stepper.start` and :meth:`Stepper.run`: a run in chunks of at most
  ``save.capacity`` records, each call continuing from the carry the last one returned
  (progress bars, checkpoints, a batch whose designs end at different times);
* :meth:`Stepper.fixed`: steps of one fixed size in one compiled ``lax.scan``.
"""

from __future__ import annotations

import dataclasses
import functools
import math
from typing import Any, NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from bristlecrawler.errors import InputError, SolverError
from bristlecrawler.fe.control import DEFAULT_CONTROL, StepControl
from bristlecrawler.fe.drivers import (
    driver_start,
    make_batch_driver,
    make_driver,
    make_host_driver,
)
from bristlecrawler.fe.dynamics import DynState, make_step
from bristlecrawler.fe.integrator import Integrator
from bristlecrawler.fe.status import STEP_TOO_SMALL, is_fatal, message

LOOPS = ("host", "compiled", "batch")


def step_time(state, params):
    """The default record: the time (s) of each accepted step."""
    return {"t": state.t}


@dataclasses.dataclass(frozen=True)
class SaveAt:
    """What a stepper records after every accepted step.

    Attributes:
        observe: ``observe(state, params) -> pytree`` of arrays (jittable and hashable: a
            module-level function or a frozen object; the crawler's observer is one).
        capacity: rows one call of :meth:`Stepper.run` holds at most (a whole run takes
            as many calls as it needs).
    """

    observe: Any = step_time
    capacity: int = 1024

    def __post_init__(self) -> None:
        if not (isinstance(self.capacity, int) and self.capacity >= 1):
            raise InputError(f"capacity must be a whole number >= 1, got {self.capacity!r}")


class BatchCarry(NamedTuple):
    """The carry of a ``"batch"`` stepper: every design's :class:`DriverCarry` and its
    step in progress (:class:`~.drivers.Pending`), stacked on the design axis."""

    carry: Any
    pending: Any


class Chunk(NamedTuple):
    """What one :meth:`Stepper.run` returns: the ``carry`` to continue from, the
    ``records`` (a pytree of arrays whose first ``n`` rows are this call's steps: the
    compiled loop's hold ``save.capacity`` rows, the host loop's ``n``, None for none),
    ``n`` and whether the run ``failed`` (a step could not be cut)."""

    carry: Any
    records: Any
    n: Any
    failed: Any


class BatchChunk(NamedTuple):
    """:class:`Chunk` of a batch, every field per design, and ``t_stop`` (each design's
    chunk end) and ``iterations`` (of the batched loop: its utilisation is the designs'
    Newton iterations over ``designs * iterations``)."""

    carry: Any
    records: Any
    n: Any
    failed: Any
    t_stop: Any
    iterations: Any


@dataclasses.dataclass(frozen=True)
class Solution:
    """A whole run (:meth:`Stepper.solve`): the final ``state``, the accepted steps'
    ``times`` (s; empty without a step) and ``records`` (the observer's rows stacked, None
    without a step),
    ``ok`` and ``message``, the counts of accepted and rejected steps and of Newton
    iterations, and ``status``: the last attempt's status (STEP_TOO_SMALL where the step
    could not be cut further, with the failure that made it in ``cause``)."""

    state: DynState
    times: np.ndarray
    records: Any
    ok: bool
    message: str
    steps: int
    rejected: int
    iterations: int
    status: int
    cause: int


@dataclasses.dataclass(frozen=True)
class Stepper:
    """Adaptive time stepping of one structure (see the module). ``integrator`` None is
    HHT-alpha's defaults; ``check(previous, new) -> ratio`` (jittable, hashable;
    optional) gets the records of the last accepted state and of a converged step and
    returns the step's error estimate over its tolerance: a ratio above 1 cuts the step
    like a failure (status STEP_ERROR), and the step grows only where the ratio leaves
    room (``ratio * grow**3 <= 1``). ``parallel_trials`` (batch only): Newton's line
    search makes all its trials at once, the same results (off the CPU, a batched loop
    otherwise makes as many trials as its longest search)."""

    topology: Any
    terms: tuple = ()
    integrator: Integrator | None = None
    save: SaveAt = SaveAt()
    control: StepControl = DEFAULT_CONTROL
    check: Any = None
    loop: str = "host"
    parallel_trials: bool = False

    def __post_init__(self) -> None:
        if self.loop not in LOOPS:
            raise InputError(f"loop must be one of {', '.join(LOOPS)}, got {self.loop!r}")
        if self.integrator is None:
            object.__setattr__(self, "integrator", Integrator.hht())
        if not isinstance(self.integrator, Integrator):
            raise InputError(f"integrator must be an fe.Integrator, got {self.integrator!r}")
        if not isinstance(self.save, SaveAt):
            raise InputError(f"save must be an fe.SaveAt, got {self.save!r}")
        if self.parallel_trials and self.loop != "batch":
            raise InputError("parallel_trials is an option of the batch loop")

    @classmethod
    def of(cls, model, **kw) -> Stepper:
        """The stepper of a built model (its topology and terms)."""
        return cls(model.topology, model.terms, **kw)

    # -- the loop --------------------------------------------------------------------

    @property
    def program(self):
        """The loop itself, cached per stepper: for ``"host"`` and ``"compiled"``
        ``(carry, params, t_end, dt_min, dt_max) -> (carry, records, n, failed)``; for
        ``"batch"`` the compiled ``(carry, pending, params, t_stop, t_end, chunk, dt_min,
        dt_max, checked) -> (carry, pending, records, n, failed, t_stop, iterations)``,
        every argument stacked by design (for callers that compile it ahead of time)."""
        if self.loop == "host":
            return make_host_driver(*self._driver_args())
        if self.loop == "compiled":
            return make_driver(*self._driver_args())
        return make_batch_driver(*self._driver_args(), self.parallel_trials).run

    def _driver_args(self) -> tuple:
        return (
            self.topology,
            self.terms,
            self.integrator,
            self.save.observe,
            self.save.capacity,
            self.control,
            self.check,
        )

    def start(self, state, dt, params=None):
        """The first carry of a run from ``state`` with a first step of ``dt`` (s). For a
        batch: a sequence of states and one of first steps, one of each per design, and
        the designs' ``params`` stacked (:func:`stack`); returns a :class:`BatchCarry`."""
        if self.loop != "batch":
            return driver_start(state, dt)
        if params is None:
            raise InputError("a batch starts from the designs' params, stacked (fe.stack)")
        states, dts = list(state), list(np.broadcast_to(np.asarray(dt, float), (len(state),)))
        carry = stack([driver_start(s, h) for s, h in zip(states, dts, strict=True)])
        driver = make_batch_driver(*self._driver_args(), self.parallel_trials)
        return BatchCarry(carry, driver.pending(carry, params))

    def run(self, carry, params, t_end, dt_min, dt_max, *, t_stop=None, chunk=None, checked=True):
        """Steps from ``carry`` towards ``t_end`` (s) until the records are full
        (``save.capacity``), the end is reached, or a step cannot be cut (dt/2 below
        ``dt_min``, or at once on a fatal status). Returns a :class:`Chunk`.

        A batch (every argument stacked by design) steps each design in chunks of
        simulated time, as a single run's caller would call :meth:`run`: to ``t_stop``
        (default ``t_end``), then to ``min(t + chunk, t_end)`` (default: no chunks), and
        so on, inside the loop; ``checked`` False bounds a design's steps by the check's
        ``created(previous, new)`` instead (the energy a step creates alone). Returns a
        :class:`BatchChunk`."""
        if self.loop != "batch":
            return Chunk(*self.program(carry, params, t_end, dt_min, dt_max))
        designs = jnp.shape(carry.carry.state.t)

        def each(x, dtype=jnp.float64):  # a number for every design, or one for all
            return jnp.broadcast_to(jnp.asarray(x, dtype), designs)

        t_end = each(t_end)
        t_stop = t_end if t_stop is None else each(t_stop)
        chunk = t_end if chunk is None else each(chunk)
        args = (t_stop, t_end, chunk, each(dt_min), each(dt_max), each(checked, bool))
        out = self.program(carry.carry, carry.pending, params, *args)
        c, pending, records, n, failed, stop, its = out
        return BatchChunk(BatchCarry(c, pending), records, n, failed, stop, its)

    def solve(self, state, params, t_end, dt, *, dt_min=None, dt_max=None, throw=True):
        """A whole run from ``state`` to ``t_end`` (s), first step ``dt`` (s), steps in
        [dt_min, dt_max] (defaults dt/1e4 and dt). Returns a :class:`Solution`; raises
        :class:`SolverError` (where and why) if ``throw`` and a step cannot be cut."""
        if self.loop == "batch":
            raise InputError("solve runs one design: use start and run for a batch")
        if not (dt > 0.0 and math.isfinite(dt)):
            raise InputError(f"dt must be positive, got {dt}")
        row = jax.eval_shape(self.save.observe, state, params)
        if not (isinstance(row, dict) and "t" in row):
            raise InputError(
                "solve records the time of each step: the observer (SaveAt.observe) must "
                "return a mapping with a 't' entry"
            )
        dt_min = dt * 1e-4 if dt_min is None else dt_min
        dt_max = dt if dt_max is None else dt_max
        carry, rows, failed = self.start(state, dt), [], False
        eps = 1e-12 * max(1.0, abs(t_end))
        while float(carry.state.t) < t_end - eps and not failed:
            carry, records, n, failed = self.run(carry, params, t_end, dt_min, dt_max)
            failed, n = bool(failed), int(n)
            if n:
                rows.append(jax.tree.map(lambda b, n=n: np.asarray(b)[:n], records))
        records = jax.tree.map(lambda *r: np.concatenate(r), *rows) if rows else None
        steps, cause = int(carry.accepted), int(carry.cause)
        msg = "converged"
        if failed:
            # The attempt that failed, with its own status (the loop's is STEP_TOO_SMALL).
            last = dataclasses.replace(carry.info, status=jnp.asarray(cause))
            msg = message(last, f"dynamics, step {steps + 1}")
            if not is_fatal(cause):
                msg += f"; dt cut below dt_min = {dt_min:g} s"
            if throw:
                raise SolverError(msg)
        times = np.zeros(0) if records is None else np.asarray(records["t"])
        return Solution(
            state=carry.state,
            times=times,
            records=records,
            ok=not failed,
            message=msg,
            steps=steps,
            rejected=int(carry.rejected),
            iterations=int(carry.iterations),
            status=STEP_TOO_SMALL if failed and not is_fatal(cause) else int(carry.info.status),
            cause=cause,
        )

    def fixed(self, state, params, dt: float, n_steps: int):
        """``n_steps`` steps of ``dt`` (s) in one compiled ``lax.scan`` (no step control,
        nothing recorded): (final state, StepInfo stacked over the steps). A failed step
        leaves the state as it was, so check the infos (:func:`status.check`)."""
        return _scan(self.step(), state, params, jnp.asarray(dt), n_steps)

    def step(self):
        """The compiled single step ``step(state, params, dt) -> (state, StepInfo)``."""
        return make_step(self.topology, self.terms, self.integrator)


@functools.partial(jax.jit, static_argnums=(0, 4))
def _scan(step, state, params, dt, n_steps):
    def body(s, _):
        return step(s, params, dt)

    return jax.lax.scan(body, state, None, length=n_steps)


def stack(trees):
    """Pytrees of equal structure (designs' states, parameters) stacked on a new leading
    (design) axis."""
    return jax.tree.map(lambda *x: jnp.stack([jnp.asarray(v) for v in x]), *trees)


def solve(
    model,
    state,
    t_end: float,
    dt: float,
    *,
    integrator: Integrator | None = None,
    save: SaveAt | None = None,
    control: StepControl = DEFAULT_CONTROL,
    check=None,
    loop: str = "host",
    dt_min: float | None = None,
    dt_max: float | None = None,
    throw: bool = True,
) -> Solution:
    """A whole run of ``model`` from ``state`` to ``t_end`` (s): ``Stepper.of(model,
    ...).solve(state, model.params, t_end, dt, ...)`` (see :class:`Stepper`)."""
    stepper = Stepper.of(
        model,
        integrator=integrator,
        save=SaveAt() if save is None else save,
        control=control,
        check=check,
        loop=loop,
    )
    return stepper.solve(state, model.params, t_end, dt, dt_min=dt_min, dt_max=dt_max, throw=throw)


__all__ = ["BatchCarry", "BatchChunk", "Chunk", "SaveAt", "Solution", "Stepper", "solve", "stack"]
