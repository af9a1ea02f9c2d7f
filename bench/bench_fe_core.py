"""Benchmark of the FE core: cost per Newton iteration and per time step vs mesh size.

Structure: the two-bristle crawler of ``bristlecrawler.verification.structures`` (paper
bristles, alpha = pi/4), n_elem elements in total (n_elem/2 per bristle). Statics: body
clamped, gravity. Dynamics: free body (bordered banded tangent), gravity and the actuated
length, HHT alpha = -0.05, fixed dt = 1e-3 s, in one compiled ``lax.scan``.
Compile time is reported separately (first call minus a second, warm call).

    python bench/bench_fe_core.py [--steps 10000]
"""

from __future__ import annotations

import argparse
import time

import jax
import numpy as np

from bristlecrawler.fe import (
    Integrator,
    StaticOptions,
    enable_compilation_cache,
    initial_state,
    run_fixed,
    solve_static,
)
from bristlecrawler.fe.dynamics import make_step
from bristlecrawler.verification.structures import two_bristle_crawler


def _block(x):
    return jax.tree.map(lambda a: a.block_until_ready() if hasattr(a, "block_until_ready")
                        else a, x)


def static_case(n: int):
    s, _ = two_bristle_crawler(n // 2, fix_body=True)
    m = s.build()
    opts = StaticOptions(rtol=1e-10)
    t0 = time.perf_counter()
    solve_static(m, options=opts)
    first = time.perf_counter() - t0
    t0 = time.perf_counter()
    res = solve_static(m, options=opts, check_support=False)
    warm = time.perf_counter() - t0
    its = sum(int(i.iterations) for i in res.infos)
    return {"compile": first - warm, "solve": warm, "iterations": its,
            "per_iter": warm / max(its, 1), "rel_res": float(res.infos[-1].rel_residual),
            "ok": res.ok}


def dynamic_case(n: int, steps: int, dt: float = 1e-3):
    s, _ = two_bristle_crawler(n // 2)
    m = s.build()
    s0 = initial_state(m)
    ig = Integrator.hht()
    t0 = time.perf_counter()
    _block(run_fixed(m, s0, m.params, dt, steps, ig))
    first = time.perf_counter() - t0
    t0 = time.perf_counter()
    fin, infos = _block(run_fixed(m, s0, m.params, dt, steps, ig))
    warm = time.perf_counter() - t0
    its = np.asarray(infos.iterations)
    ok = bool(np.all(np.asarray(infos.status) == 0))
    return {"compile": first - warm, "run": warm, "per_step": warm / steps,
            "per_iter": warm / max(its.sum(), 1), "mean_iter": float(its.mean()), "ok": ok,
            "n_red": m.topology.n_red, "border": m.topology.n_border,
            "step": make_step(m.topology, m.terms, ig), "model": m, "s0": s0, "final": fin}


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--steps", type=int, default=10_000, help="steps of the long run")
    ap.add_argument("--sizes", type=int, nargs="*", default=[20, 50, 100, 200])
    args = ap.parse_args()
    enable_compilation_cache()
    print(f"jax {jax.__version__} on {jax.devices()[0].platform}; HHT alpha=-0.05, dt=1e-3 s")
    print(f"{'elements':>8} {'DOFs':>5} {'border':>6} | {'static: iters':>13} {'ms/iter':>8} "
          f"{'|R|/F':>9} {'compile s':>9} | {'dyn: ms/step':>12} {'ms/iter':>8} "
          f"{'iters/step':>10} {'compile s':>9}")
    last = None
    for n in args.sizes:
        st = static_case(n)
        dy = dynamic_case(n, 200)
        last = dy
        print(f"{n:>8} {dy['n_red']:>5} {dy['border']:>6} | {st['iterations']:>13} "
              f"{1e3 * st['per_iter']:>8.2f} {st['rel_res']:>9.1e} {st['compile']:>9.1f} | "
              f"{1e3 * dy['per_step']:>12.2f} {1e3 * dy['per_iter']:>8.2f} "
              f"{dy['mean_iter']:>10.2f} {dy['compile']:>9.1f}"
              + ("" if st["ok"] and dy["ok"] else "  (FAILED)"))
    m, state = last["model"], last["s0"]
    # Chunks of the already compiled 200-step scan: no new compile for the long run.
    t0 = time.perf_counter()
    its, ok = [], True
    for _ in range(args.steps // 200):
        state, infos = _block(run_fixed(m, state, m.params, 1e-3, 200, Integrator.hht()))
        its.append(np.asarray(infos.iterations))
        ok = ok and bool(np.all(np.asarray(infos.status) == 0))
    wall = time.perf_counter() - t0
    n_steps = 200 * (args.steps // 200)
    print(f"\n{n_steps} HHT steps, {args.sizes[-1]} elements: {wall:.1f} s wall, "
          f"{1e3 * wall / n_steps:.2f} ms/step, mean Newton iterations "
          f"{float(np.mean(np.concatenate(its))):.2f}, all converged: {ok}, "
          f"t_end = {float(state.t):.2f} s")


if __name__ == "__main__":
    main()
