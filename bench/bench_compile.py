"""Tracing and compiling the crawler's step program, and what the compiled step costs.

Traces, lowers and compiles the step of a scenario's structure in this process, with the
caches off, and times the compiled step on the attempts kept by ``bench_step.py --save``.
XLA's compiler options come from the environment, so the same file compares them in
fresh processes::

    python bench/bench_step.py --save runs/attempts.pkl       # once
    python bench/bench_compile.py --load runs/attempts.pkl
    XLA_FLAGS=--xla_backend_optimization_level=0 python bench/bench_compile.py --load ...

Prints one line: the flags, the trace-and-lower and compile times (s), and the step's
cost per Newton iteration on the attempts (the fastest of ``--calls`` calls each). Nothing
is asserted. Loading a pickle runs code from it: load only files you made.
"""

from __future__ import annotations

import argparse
import os
import pickle
import sys
import time
from pathlib import Path


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--load", type=Path, required=True, help="attempts of bench_step.py")
    ap.add_argument("--calls", type=int, default=5, help="timed calls per attempt")
    a = ap.parse_args()
    if not a.load.is_file():
        print(f"error: --load {a.load}: no such file", file=sys.stderr)
        sys.exit(2)
    os.environ["BRISTLECRAWLER_NO_JAX_CACHE"] = "1"  # a cold start: nothing stored
    import jax
    import jax.numpy as jnp
    import numpy as np

    from bristlecrawler.crawler import build
    from bristlecrawler.fe.dynamics import make_step
    from bristlecrawler.scenario.convert import to_spec
    from bristlecrawler.scenario.load import apply_overrides, load_scenario

    saved = pickle.loads(a.load.read_bytes())
    spec = to_spec(apply_overrides(load_scenario(saved["scenario"]), saved["sets"]))
    model = build(spec).model
    ig = spec.solver.integrator(spec.contact.penetration_limit)
    step = make_step(model.topology, model.terms, ig)
    state, params, dt, _, _ = saved["attempts"][0]
    state, params = jax.device_put((state, params))
    t0 = time.perf_counter()
    lowered = step.lower(state, params, jnp.asarray(dt))
    t1 = time.perf_counter()
    compiled = lowered.compile()
    t2 = time.perf_counter()
    total, iterations = 0.0, 0
    for state, params, dt, _, _ in saved["attempts"]:
        args = jax.device_put((state, params, jnp.asarray(dt)))
        jax.block_until_ready(compiled(*args))
        best = np.inf
        for _ in range(a.calls):
            t = time.perf_counter()
            new, info = compiled(*args)
            jax.block_until_ready(new)
            best = min(best, time.perf_counter() - t)
        total += best
        iterations += int(info.iterations)
    print(
        f"XLA_FLAGS={os.environ.get('XLA_FLAGS', '')!r}: trace and lower {t1 - t0:.1f} s, "
        f"compile {t2 - t1:.1f} s; {len(saved['attempts'])} attempts, {iterations} Newton "
        f"iterations, {1e3 * total / max(iterations, 1):.3f} ms per iteration"
    )


if __name__ == "__main__":
    main()
