"""Where a Newton iteration of the FE crawler's step spends its time.

Runs one cycle of a shipped scenario (default ``paper``) to a state with its tips on the
substrate, then times, each as its own compiled program on that state: a whole time step
(per Newton iteration), the step's residual (it evaluates the forces at the step's start
too, which the step does once), its banded tangent (the coloured JVPs of
:func:`fe.banded.extract`, the residual included), the block-tridiagonal solve, and the
two parts of the residual alone: the beams' internal force and the contact terms. Prints
a table (median of ``--repeat`` calls after one warm-up call each; compilation apart);
nothing is asserted.

    python bench/bench_iteration.py [--scenario paper] [--set bristle.elements=20]
                                    [--repeat 200]
"""

from __future__ import annotations

import argparse
import time


def timed(fn, args, repeat: int) -> tuple[float, float]:
    """(compile + first call, median of ``repeat`` calls) in s."""
    import jax
    import numpy as np

    t0 = time.perf_counter()
    jax.block_until_ready(fn(*args))
    first = time.perf_counter() - t0
    walls = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        jax.block_until_ready(fn(*args))
        walls.append(time.perf_counter() - t0)
    return first, float(np.median(walls))


def programs(ctx):
    """The programs to time on the context's state: name -> (jitted fn, args)."""
    import dataclasses

    import jax
    import jax.numpy as jnp

    from bristlecrawler import fe
    from bristlecrawler.fe import assembly, banded

    m, state = ctx.model, ctx.state
    topo, terms, params = m.topology, m.terms, m.params
    ig = ctx.spec.solver.integrator(ctx.spec.contact.penetration_limit)
    dt = jnp.asarray(1e-3)

    def equations(state, params):
        return ig.equations(state, ig.init(state, params, topo, terms), params, dt, topo, terms)[1]

    @jax.jit
    def residual(state, params, q):
        return equations(state, params)(q)

    @jax.jit
    def tangent(state, params, q):
        return banded.extract(lambda q: equations(state, params)(q)[0], q, topo)

    @jax.jit
    def solve(system, rhs):
        return banded.solve(system, rhs, topo)

    @jax.jit
    def internal(u):
        return assembly.internal_force(u, params, topo)

    @jax.jit
    def contact(u, v, history):
        return assembly.terms_residual(u, v, state.t, history, params, terms)

    @jax.jit
    def bare_tangent(state, params, q):
        # The same step without the contact terms: what the tangent costs for the beams,
        # the inertia and the constraints alone.
        bare = dataclasses.replace(state, history=())
        res = ig.equations(bare, ig.init(bare, params, topo, ()), params, dt, topo, ())[1]
        return banded.extract(lambda q: res(q)[0], q, topo)

    step = fe.make_step(topo, terms, ig)
    bare_params = dataclasses.replace(params, extra=())
    return {
        "time step": (step, (state, params, dt)),
        "residual": (residual, (state, params, state.q)),
        "tangent (residual included)": (tangent, (state, params, state.q)),
        # The tangent's output, once it is compiled.
        "tangent without contact terms": (bare_tangent, (state, bare_params, state.q)),
        "solve": (solve, lambda: tangent(state, params, state.q)[::-1]),
        "internal force": (internal, (state.u,)),
        "contact terms": (contact, (state.u, state.v, state.history)),
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scenario", default="paper")
    ap.add_argument("--set", dest="sets", action="append", default=[])
    ap.add_argument("--repeat", type=int, default=200)
    a = ap.parse_args()

    from bristlecrawler.crawler import build
    from bristlecrawler.crawler.runner import DEFAULT_STAGES, run_stages
    from bristlecrawler.fe import enable_compilation_cache
    from bristlecrawler.scenario.convert import to_spec
    from bristlecrawler.scenario.load import apply_overrides, load_scenario

    enable_compilation_cache()
    sc = apply_overrides(load_scenario(a.scenario), [*a.sets, "actuation.cycles=1"])
    ctx = run_stages(build(to_spec(sc)), DEFAULT_STAGES)
    print(
        f"scenario {sc.name}, {sc.bristle.elements} elements per bristle, "
        f"{ctx.model.topology.n_red} unknowns, state after one cycle; "
        f"{ctx.iterations / max(len(ctx.records) - 1, 1):.1f} Newton iterations per step"
    )
    head = f"{'program':>28} {'first call s':>13} {'ms per call':>12} {'ms per iteration':>17}"
    print(head)
    print("-" * len(head))
    for name, (fn, args) in programs(ctx).items():
        first, wall = timed(fn, args() if callable(args) else args, a.repeat)
        per_it = ""
        if name == "time step":
            its = max(int(fn(*args)[1].iterations), 1)
            per_it = f"{1e3 * wall / its:17.3f}"
        print(f"{name:>28} {first:13.1f} {1e3 * wall:12.3f} {per_it}")


if __name__ == "__main__":
    main()
