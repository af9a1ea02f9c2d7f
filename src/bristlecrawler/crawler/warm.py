"""The programs a crawler run calls, compiled (or loaded from the persistent cache) at
its start, side by side, so that the run finds them ready."""

from __future__ import annotations

import time
from concurrent.futures import ThreadPoolExecutor

import jax
import jax.numpy as jnp

from bristlecrawler import fe
from bristlecrawler.fe.dynamics import DynState
from bristlecrawler.fe.modal import mass_matrix
from bristlecrawler.fe.static import tangent
from bristlecrawler.fe.terms import init_histories


def compile_programs(ctx, *, step: bool, modal: bool):
    """(The initial state of ``ctx.model``, seconds), with the programs a run calls
    compiled (or loaded from the persistent cache) at once, each in a thread: the initial
    state's, the observer's, the dynamic step's (``step``) and the modal analysis's
    (``modal``). XLA compiles outside Python's lock, so the programs compile side by side
    (``RunOptions.compile_threads``; ``bench/bench_crawler.py --compile-threads``
    compares). The programs other than the initial state's are called on a state of
    zeros of the same shapes and types, so that the run finds them compiled."""
    model = ctx.model
    t0 = time.perf_counter()
    topo, params = model.topology, model.params
    observe = ctx.crawler.observer()
    integrator = ctx.spec.solver.integrator(ctx.spec.contact.penetration_limit)
    key = (topo, model.terms, observe, integrator if step else None, modal)
    if ctx.batched and key in _WARM:  # an earlier design of the batch compiled them
        return fe.initial_state(model), 0.0
    zeros = jnp.zeros((topo.n_nodes, 3))
    like = DynState(
        jnp.asarray(0.0, jnp.float64),
        jnp.zeros(topo.n_red),
        zeros,
        zeros,
        zeros,
        init_histories(model),
    )
    jobs = [lambda: fe.initial_state(model), lambda: observe(like, params)]
    if step:
        # Made here, called in a thread: two threads must not build one program twice.
        run_step = fe.make_step(topo, model.terms, integrator)
        dt = jnp.asarray(float(ctx.options.dt0) * 1e-3)
        jobs.append(lambda: run_step(like, params, dt))
    if modal:
        # The arguments' types of ModalDamping's fe.modes call.
        jobs += [
            lambda: tangent(model, like.q, 0.0, 1.0, like.history),
            lambda: mass_matrix(model, like.q, 0.0, 1.0),
        ]
    with ThreadPoolExecutor(min(len(jobs), ctx.options.compile_threads)) as pool:
        futures = [pool.submit(job) for job in jobs]
        done = [jax.block_until_ready(f.result()) for f in futures]
    _WARM.add(key)
    return done[0], time.perf_counter() - t0


#: What :func:`compile_programs` has compiled in this process, by what the programs
#: depend on: the designs of a batch after the first only make their initial state (a
#: single run still calls them, and reports the time a cache load takes).
_WARM: set = set()
