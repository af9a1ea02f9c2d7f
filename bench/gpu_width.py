"""Cost of one batched Newton iteration by batch width (is the batched program bound by
launches or by arithmetic?).

B copies of the ``paper`` design (so every design takes the same iterations: utilisation 1)
fall under gravity from the reference state for ``--span`` s with the batched driver
(the batch loop of :class:`fe.Stepper`, the program of :func:`crawler.run_batch`). For each width:
the compilation, then the run's wall time over its batched Newton iterations. If the
time per iteration hardly grows with B, the program is bound by its launches and wider
batches run more designs per minute; if it grows as B, by arithmetic.

    python bench/gpu_width.py [--widths 1024 8192] [--span 0.5] [--cpu]
"""

from __future__ import annotations

import argparse
import time

import jax
import numpy as np


def tile(tree, width: int):
    """``width`` copies of every leaf of ``tree`` on a new leading axis."""
    return jax.tree.map(lambda x: np.broadcast_to(x, (width, *np.shape(x))), tree)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--widths", type=int, nargs="+", default=[1024, 8192])
    ap.add_argument("--span", type=float, default=0.5)
    ap.add_argument("--cpu", action="store_true", help="run on a CPU too (to try the script)")
    a = ap.parse_args()

    from bristlecrawler import fe
    from bristlecrawler.crawler import CrawlerSpec, build
    from bristlecrawler.crawler.runner import RunContext, RunOptions

    if jax.default_backend() != "gpu" and not a.cpu:
        print(f"no GPU: JAX computes on {jax.default_backend()}")
        return
    device = jax.devices()[0]
    spec = CrawlerSpec.paper()
    ctx = RunContext(build(spec), RunOptions(), None, t_end=0.0)
    ctx.damping = fe.Rayleigh.from_ratio(0.15, ctx.options.settle_omega, "mass")
    ctx.model = ctx.damping.apply(ctx.crawler.model)
    state = fe.initial_state(ctx.model)
    stepper = ctx.stepper(True, "batch")
    print(f"{device.device_kind}; JAX {jax.__version__}; paper, gravity step of {a.span} s")
    head = f"{'B':>6} {'compile s':>10} {'run s':>8} {'iterations':>11} {'ms/it':>8}"
    head += f" {'us/design-it':>13}"
    print(head + "\n" + "-" * len(head), flush=True)
    for width in a.widths:
        t0 = time.perf_counter()
        params = tile(ctx.model.params, width)
        carry, pending = stepper.start([state] * width, [ctx.options.dt0] * width, params)
        vec = np.full(width, 1.0)
        args = (carry, pending, params, a.span * vec, a.span * vec)
        args += (a.span * vec,)
        args += (spec.solver.dt_min * vec, min(spec.solver.dt_max, 0.01) * vec)
        args += (np.zeros(width, bool),)
        args = jax.tree.map(lambda x: jax.device_put(np.ascontiguousarray(x)), args)
        program = stepper.program.lower(*args).compile()
        compile_s = time.perf_counter() - t0
        t0, its = time.perf_counter(), 0
        c, pend = args[:2]
        while True:  # returns to the host when the buffers fill
            c, pend, _, _, failed, _, n = program(c, pend, *args[2:])
            its += int(n)
            if float(np.min(np.asarray(c.state.t))) >= a.span - 1e-9 or bool(np.any(failed)):
                break
        wall = time.perf_counter() - t0
        print(
            f"{width:6d} {compile_s:10.1f} {wall:8.2f} {its:11d} {1e3 * wall / its:8.2f} "
            f"{1e6 * wall / its / width:13.3f}",
            flush=True,
        )


if __name__ == "__main__":
    main()
