"""The loops behind :class:`fe.Stepper` (:mod:`.stepping`, the door to use).

Each takes steps of the dynamic step of :mod:`.dynamics` with one rule
(:meth:`StepControl.decide`: halve on failure, grow after easy steps, stay within
[dt_min, dt_max]) and records an observer after every accepted step (and, given a
``check``, rejects a converged step whose error estimate the check refuses):
:func:`make_driver` as one compiled XLA loop (the form for a GPU), :func:`make_host_driver`
as a host loop around the compiled step (the smaller program to compile on a CPU; as fast
per run there), :func:`make_batch_driver` as the compiled loop for designs of one
structure, one Newton iteration of every design at a time. :func:`driver_start` makes the
first carry.
"""

from __future__ import annotations

import dataclasses
import functools
from typing import Any, NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from bristlecrawler._pytree import pytree
from bristlecrawler.fe.control import DEFAULT_CONTROL, StepControl, march
from bristlecrawler.fe.dynamics import (
    DynState,
    StepInfo,
    make_step,
    step_result,
    step_solver,
)
from bristlecrawler.fe.integrator import Integrator
from bristlecrawler.fe.programs import stored
from bristlecrawler.fe.status import SUCCESS


@pytree()
class DriverCarry:
    """State of the compiled adaptive driver between chunks: the dynamic state, the next
    step size (s), counters (accepted steps, rejected steps, Newton iterations of accepted
    and rejected steps), the last step's info, and ``cause``: the status of the last
    attempt itself (which failure made a STEP_TOO_SMALL)."""

    state: DynState
    dt: Any
    accepted: Any
    rejected: Any
    iterations: Any
    info: StepInfo
    cause: Any


@functools.lru_cache(maxsize=32)
def make_driver(
    topo,
    terms,
    integrator: Integrator | None,
    observe,
    capacity: int,
    control: StepControl = DEFAULT_CONTROL,
    check=None,
):
    """Compiled adaptive stepping: ``run(carry, params, t_end, dt_min, dt_max)``.

    One ``lax.while_loop`` takes steps from ``carry.state`` until ``t_end`` (s), until
    ``capacity`` steps are accepted, or until a failed step cannot be cut (dt / 2 below
    ``dt_min``, or at once on a fatal status, :data:`status.FATAL`). The step rules are
    ``control``'s (:class:`StepControl`), within [dt_min, dt_max].
    ``observe(state, params) -> pytree`` (jittable, static, hashable) is recorded after
    every accepted step into a buffer of ``capacity`` rows. ``check(previous, new) -> ratio``
    (jittable, static, hashable; optional) gets the records of the last accepted state and
    of a converged step and returns the step's error estimate over its tolerance: a step
    with a ratio above 1 is cut like a failed one (status STEP_ERROR), and the step only
    grows when the ratio leaves room for it (``ratio * grow**3 <= 1``, a local error of
    third order), so an estimate built from the records (the step's energy balance, say)
    controls the step size. Returns (carry, buffer,
    n_recorded, failed). No host round trip per step: on a CPU this removes the dispatch
    and the synchronisation of two programs per step, and it is the form that runs on a GPU.
    """
    step = make_step(topo, terms, integrator)
    start, cond, body, _ = _loop(step, observe, capacity, control, check)

    @jax.jit
    def run(carry, params, t_end, dt_min, dt_max):
        args = (params, t_end, dt_min, dt_max)
        c = jax.lax.while_loop(
            lambda c: cond(c, *args), lambda c: body(c, *args), start(carry, *args)
        )
        carry, buf, k, failed, _ = c
        return carry, buf, k, failed

    return stored(
        run, "fe.drivers.make_driver", topo, terms, integrator, observe, capacity, control, check
    )


def _loop(step, observe, capacity: int, control: StepControl, check):
    """The compiled driver's loop for one design: ``start(carry, *args)`` makes the loop
    state (carry, buffer, recorded rows, failed, last record), ``cond(c, *args)`` and
    ``body(c, *args)`` with ``args = (params, t_end, dt_min, dt_max)``, and ``end(c, new,
    info, h, *args, checked)``, the body's bookkeeping of an attempted step of ``h`` that
    gave ``(new, info)``. Shared by :func:`make_driver` and, vmapped, by
    :func:`make_batch_driver` (which takes its steps one Newton iteration at a time)."""

    def start(carry, params, t_end, dt_min, dt_max):
        proto = observe(carry.state, params)
        buf = jax.tree.map(
            lambda x: jnp.zeros((capacity, *jnp.shape(x)), jnp.result_type(x)), proto
        )
        return carry, buf, jnp.asarray(0), jnp.asarray(False), proto

    def cond(c, params, t_end, dt_min, dt_max):
        carry, _, k, failed, _ = c
        eps = 1e-12 * jnp.maximum(1.0, jnp.abs(t_end))
        return (carry.state.t < t_end - eps) & (k < capacity) & ~failed

    def body(c, params, t_end, dt_min, dt_max):
        carry = c[0]
        h = jnp.minimum(carry.dt, t_end - carry.state.t)
        new, info = step(carry.state, params, h)
        return end(c, new, info, h, params, t_end, dt_min, dt_max)

    def end(c, new, info, h, params, t_end, dt_min, dt_max, checked=True):
        carry, buf, k, _, last = c
        rec = observe(new, params)
        # ``checked`` False (a batch's gravity step): the check's bound on the energy a
        # step creates alone (its ``created``), as a single run's check without losses.
        # A single run's loop passes the literal True: one ratio, nothing else traced.
        if check is None:
            ratio = None
        elif checked is True:
            ratio = check(last, rec)
        else:
            ratio = jnp.where(checked, check(last, rec), check.created(last, rec))
        out = control.decide(info.status, info.iterations, h, carry.dt, dt_min, dt_max, ratio)
        good, dt, failed, cause = out.good, out.dt, out.failed, out.cause
        info = dataclasses.replace(info, status=out.status)
        last = jax.tree.map(lambda r, o: jnp.where(good, r, o), rec, last)
        buf = jax.tree.map(lambda b, r: b.at[k].set(jnp.where(good, r, b[k])), buf, rec)
        nxt = DriverCarry(
            state=jax.tree.map(lambda n, o: jnp.where(good, n, o), new, carry.state),
            dt=dt,
            accepted=carry.accepted + good,
            rejected=carry.rejected + ~good,
            iterations=carry.iterations + info.iterations,
            info=info,
            cause=cause,
        )
        return nxt, buf, k + good, failed, last

    return start, cond, body, end


class Pending(NamedTuple):
    """A design's attempted step inside the batched loop: Newton's iterate (``nc``), the
    step size ``h`` (s), what the integrator's steps from the design's state share
    (``start``, :meth:`Integrator.init`), and ``fresh``: the next iteration starts a step."""

    nc: Any
    h: Any
    start: Any
    fresh: Any


@dataclasses.dataclass(frozen=True)
class BatchDriver:
    """:func:`make_batch_driver`'s program ``run`` and ``pending(carry, params)``, the
    :class:`Pending` of designs that start a step (stacked like ``carry``)."""

    run: Any
    pending: Any


@functools.lru_cache(maxsize=16)
def make_batch_driver(
    topo,
    terms,
    integrator: Integrator | None,
    observe,
    capacity: int,
    control: StepControl = DEFAULT_CONTROL,
    check=None,
    parallel_trials: bool = False,
) -> BatchDriver:
    """:func:`make_driver` for a batch of designs of one structure, in one compiled loop
    whose every iteration is one Newton iteration of every design, each at its own point
    of its own step: a design that needs many iterations for a step (or fails one after
    ``max_iter``) holds up no other design. ``run(carry, pending, params, t_stop, t_end,
    chunk, dt_min, dt_max, checked)`` with every argument stacked on a leading design axis
    (from :func:`.stepping.stack`; ``pending`` from :attr:`BatchDriver.pending` at the start);
    ``checked`` (bool) False bounds a design's steps by the check's ``created(previous,
    new)`` instead (the energy a step creates alone: the gravity step's bound), so that
    the gravity step runs in the same program. Each design keeps its own step size,
    rejections, Newton iterations and records, and takes the steps of its single run:
    the same operations, one iteration at a time. One that is done or has failed is
    masked (its state does not move) while the others iterate, and one design's failure
    does not stop the others.
    ``parallel_trials``: Newton's line search makes all its trials at once (the same
    results; see :func:`newton.newton_parts`), so that a batched iteration does not
    make as many trials as the batch's longest search.

    Each design steps in chunks of simulated time, as a single run's host loop calls its
    driver: to ``t_stop`` (a chunk's end caps the step), then to ``min(t + chunk,
    t_end)``, and so on, inside the loop, so that no design waits at a chunk's end for the
    others. The loop returns when every design is done or has failed, or when a design's
    buffer is full (``capacity`` rows; the caller takes the rows and calls again with the
    returned carry, pending steps and ``t_stop``). Returns (carry, pending, buffer,
    n_recorded, failed, t_stop, batch_iterations), all per design but the last: the
    iterations of the batched loop, for the utilisation ``sum(carry.iterations) / (B *
    batch_iterations)``.
    """
    ig = Integrator.hht() if integrator is None else integrator
    start, cond, _, end = _loop(None, observe, capacity, control, check)

    def solver(state, params, h, start):
        return step_solver(state, params, h, topo, terms, ig, start, parallel_trials)

    def iterate(c, pend, params, t_stop, dt_min, dt_max, checked):
        """One Newton iteration of one design: a step starts where ``pend.fresh``, and
        ends (its bookkeeping as in :func:`make_driver`) where Newton stops."""
        carry = c[0]
        state = carry.state
        h = jnp.where(pend.fresh, jnp.minimum(carry.dt, t_stop - state.t), pend.h)
        # A pending step keeps the start it began with; the integrator's init is evaluated
        # every iteration (under vmap a branch would run both sides anyway).
        start = _tree_where(pend.fresh, ig.init(state, params, topo, terms), pend.start)
        kin, parts = solver(state, params, h, start)
        nc = _tree_where(pend.fresh, parts.init, pend.nc)
        nc = _tree_where(parts.cond(nc), parts.body(nc), nc)
        ending = ~parts.cond(nc)
        new, info = step_result(state, params, h, kin, parts.result(nc), topo, terms, ig)
        done = end(c, new, info, h, params, t_stop, dt_min, dt_max, checked)
        return _tree_where(ending, done, c), Pending(nc, h, start, ending)

    def pending(carry, params):
        def one(state, p):
            zero = jnp.zeros((), state.t.dtype)
            start = ig.init(state, p, topo, terms)
            return Pending(solver(state, p, zero, start)[1].init, zero, start, True)

        shapes = jax.eval_shape(jax.vmap(one), carry.state, params)
        out = jax.tree.map(lambda x: np.zeros(x.shape, x.dtype), shapes)
        return out._replace(fresh=np.ones(out.fresh.shape, bool))

    vcond, vstart, viterate = (jax.vmap(f) for f in (cond, start, iterate))

    @jax.jit
    def run(carry, pend, params, t_stop, t_end, chunk, dt_min, dt_max, checked):
        def bbody(bc):
            c, pend, stop, n = bc
            args = (params, stop, dt_min, dt_max)
            active = vcond(c, *args)
            new = viterate(c, pend, *args, checked)
            c, pend = (_tree_where(active, x, o) for x, o in zip(new, (c, pend), strict=True))
            t, failed = c[0].state.t, c[3]
            # The host loop's test of a chunk's end, then its next chunk.
            more = (t >= stop - 1e-9) & (t < t_end - 1e-9) & ~failed
            stop = jnp.where(more, jnp.minimum(t + chunk, t_end), stop)
            return c, pend, stop, n + 1

        def bcond(bc):
            c, _, stop, _ = bc
            return jnp.any(vcond(c, params, stop, dt_min, dt_max)) & jnp.all(c[2] < capacity)

        c0 = vstart(carry, params, t_stop, dt_min, dt_max)
        c, pend, stop, n = jax.lax.while_loop(bcond, bbody, (c0, pend, t_stop, jnp.asarray(0)))
        carry, buf, k, failed, _ = c
        return carry, pend, buf, k, failed, stop, n

    key = (topo, terms, integrator, observe, capacity, control, check, parallel_trials)
    return BatchDriver(stored(run, "fe.drivers.make_batch_driver", *key), pending)


def _tree_where(mask, new, old):
    """``new`` where ``mask`` (a design's scalar or the batch's (B,) vector), else ``old``."""
    return jax.tree.map(lambda x, o: _where(mask, x, o), new, old)


def _where(mask, new, old):
    return jnp.where(mask.reshape(mask.shape + (1,) * (jnp.ndim(new) - 1)), new, old)


@functools.lru_cache(maxsize=32)
def make_host_driver(
    topo,
    terms,
    integrator: Integrator | None,
    observe,
    capacity: int,
    control: StepControl = DEFAULT_CONTROL,
    check=None,
):
    """:func:`make_driver` with the loop on the host: same arguments, same step rules, same
    results (``run(carry, params, t_end, dt_min, dt_max) -> (carry, buffer, n_recorded,
    failed)``, the buffer holding the ``n_recorded`` rows only), but each step is one call
    of the compiled :func:`make_step` and the observer.

    Why both: per run the two cost about the same on a CPU with the same iterates, but
    each compiled loop holds the whole step, so it takes longer to compile and to load
    from the cache. The host loop is the CPU default; the compiled driver is the form for
    a GPU and for ``vmap`` batches.
    """
    step = make_step(topo, terms, integrator)

    # A function that is already jitted is called as it is: the crawler's observer wrapped
    # in another jit was a second program to compile (7.5 s of the paper crawler's first
    # run) and to load.
    def jitted(f):
        return f if hasattr(f, "lower") else jax.jit(f)

    obs = jitted(observe)
    accept = None if check is None else stored(jax.jit(check), "fe.drivers.check", check)

    def run(carry, params, t_end, dt_min, dt_max):
        t_end, dt_min, dt_max = float(t_end), float(dt_min), float(dt_max)
        rows, failed = [], False
        state, dt = carry.state, float(carry.dt)
        accepted, rejected, iterations = (
            int(x) for x in (carry.accepted, carry.rejected, carry.iterations)
        )
        info, cause = carry.info, carry.cause
        last = obs(state, params) if accept is not None else None

        checked = {}  # the observed row of the last try, where the check made one

        def attempt(state, h):
            new, info = step(state, params, jnp.asarray(h))
            status, ratio = int(info.status), None
            checked.clear()
            if accept is not None and status == SUCCESS:
                checked["row"] = obs(new, params)
                ratio = float(accept(last, checked["row"]))
            return new, info, status, ratio

        tries = march(
            attempt,
            state,
            float(state.t),
            t_end,
            dt,
            dt_min,
            dt_max,
            control,
            time_of=lambda new: float(new.t),
            more=lambda: len(rows) < capacity,
        )
        for a in tries:
            out, info = a.outcome, a.info
            iterations += int(info.iterations)
            cause, dt, failed = out.cause, out.dt, out.failed
            if out.status != int(info.status):
                info = dataclasses.replace(info, status=jnp.asarray(out.status))
            if out.good:
                state = a.new
                accepted += 1
                rec = checked["row"] if checked else obs(state, params)
                rows.append(rec)
                last = rec
            else:
                rejected += 1
        carry = DriverCarry(
            state=state,
            dt=jnp.asarray(dt),
            accepted=jnp.asarray(accepted),
            rejected=jnp.asarray(rejected),
            iterations=jnp.asarray(iterations),
            info=info,
            cause=jnp.asarray(cause),
        )
        # Stacked on the host: jnp.stack would compile a program for every chunk length.
        buf = jax.tree.map(lambda *r: np.stack(r), *jax.device_get(rows)) if rows else None
        return carry, buf, len(rows), failed

    return run


def driver_start(state: DynState, dt: float) -> DriverCarry:
    """Initial :class:`DriverCarry` from a dynamic state and a first step ``dt`` (s)."""
    z = jnp.asarray(0)
    info = StepInfo(
        jnp.asarray(SUCCESS),
        z,
        jnp.asarray(0.0),
        jnp.asarray(0.0),
        state.t,
        jnp.asarray(float(dt)),
        jnp.asarray(1.0),
    )
    return DriverCarry(state, jnp.asarray(float(dt)), z, z, z, info, jnp.asarray(SUCCESS))
