"""Benchmark of the FE core: cost per Newton iteration and per time step vs mesh size.

Structure: the two-bristle crawler of ``bristlecrawler.verification.structures`` (paper
bristles at alpha = pi/4, n_elem/2 elements per bristle), body clamped at its left end
(``fix_body``: a supported structure, no contact needed), gravity, and the actuated body
length 100 - s(t), s = 20 sin^2(pi t / 20) mm, which drags the right bristle along.

* Statics: equilibrium under gravity at t = 0, the library's compiled Newton solver
  (``make_static_solver``, as ``solve_static`` calls it) from q = 0 to |R| <= 1e-10 F.
* Dynamics: HHT alpha = -0.05, fixed dt = 1 ms, from that equilibrium, ``Stepper.fixed``
  (one compiled ``lax.scan``): a 200-step chunk per size, then 10^4 steps for the largest.
* The 1e-10 solve of the largest mesh is then continued with no stopping test, to show the
  round-off floor of |R|/F next to its estimate eps |K| |q| / F.

Compile time is measured apart (``jit(...).lower(...).compile()``), with JAX's persistent
compilation cache on (``enable_compilation_cache``; ``--cache DIR`` to choose the folder,
``--no-cache`` to compare): run the script twice and the second process loads the programs
from the cache instead of compiling them. Timings are the best of a few repeats; the load
average is printed because the machine may be shared. Nothing is asserted.

    python bench/bench_fe_core.py [--sizes 20 50 100 200] [--steps 10000] [--cache DIR]
"""

from __future__ import annotations

import argparse
import math
import os
import time
from pathlib import Path

import jax
import jax.numpy as jnp
import numpy as np

from bristlecrawler.fe import (
    Integrator,
    Stepper,
    banded,
    enable_compilation_cache,
    initial_state,
)
from bristlecrawler.fe.newton import NewtonOptions
from bristlecrawler.fe.static import make_static_solver, static_residual
from bristlecrawler.fe.terms import init_histories
from bristlecrawler.verification.structures import two_bristle_crawler

RTOL = 1e-10
MAX_ITER = 30
DT = 1e-3
CHUNK = 200
HHT = Integrator.hht()
EPS = float(np.finfo(float).eps)


def build(n_elem: int):
    s, nodes = two_bristle_crawler(n_elem // 2, fix_body=True)
    return s.build(), nodes


def compile_timed(fn, *args):
    """(seconds, compiled executable) of ``jax.jit(fn)`` for ``args``."""
    t0 = time.perf_counter()
    compiled = jax.jit(fn).lower(*args).compile()
    return time.perf_counter() - t0, compiled


def best_of(fn, repeat: int):
    best, out = math.inf, None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = jax.block_until_ready(fn())
        best = min(best, time.perf_counter() - t0)
    return best, out


def static_case(n_elem: int) -> dict:
    m, nodes = build(n_elem)
    topo, p = m.topology, m.params
    solver = make_static_solver(
        topo, m.terms, NewtonOptions(tolerance=RTOL, max_iterations=MAX_ITER)
    )
    args = (jnp.zeros(topo.n_red), p, jnp.asarray(0.0), jnp.asarray(1.0), init_histories(m))
    compile_s, solve = compile_timed(solver, *args)
    wall, (q, _, info) = best_of(lambda: solve(*args), 5)
    its = int(info.iterations)
    return {
        "model": m,
        "nodes": nodes,
        "q": q,
        "n_red": topo.n_red,
        "iterations": its,
        "solve": wall,
        "per_iter": wall / its,
        "rel_res": float(info.rel_residual),
        "status": int(info.status),
        "compile": compile_s,
    }


def dynamic_case(m, q_eq, n_steps: int, repeat: int) -> dict:
    s0 = initial_state(m, q=q_eq)

    def run(state, params):
        return Stepper.of(m, integrator=HHT).fixed(state, params, DT, n_steps)

    compile_s, compiled = compile_timed(run, s0, m.params)
    wall, (final, infos) = best_of(lambda: compiled(s0, m.params), repeat)
    its = np.asarray(infos.iterations)
    return {
        "compile": compile_s,
        "run": wall,
        "per_step": wall / n_steps,
        "per_iter": wall / max(int(its.sum()), 1),
        "mean_iter": float(its.mean()),
        "max_iter": int(its.max()),
        "ok": bool(np.all(np.asarray(infos.status) == 0)),
        "final": final,
    }


def floor_study(m, q, extra_iterations: int = 8) -> dict:
    """Newton continued from the converged ``q`` with no stopping test: the |R|/F it
    stagnates at, and the estimate eps |K|_inf |q|_inf / F of the round-off floor."""
    topo, p = m.topology, m.params
    hist = init_histories(m)

    def iteration(q):
        def res(q):
            return static_residual(q, 0.0, 1.0, hist, p, topo, m.terms)

        R, F = res(q)
        _, J = banded.extract(lambda q: res(q)[0], q, topo)
        dq = -banded.solve(J, R, topo)
        rows = (jnp.abs(J.lower) + jnp.abs(J.diag) + jnp.abs(J.upper)).sum(-1).ravel()
        rows = rows + jnp.abs(J.B).sum(-1)
        K_inf = jnp.maximum(
            rows.max(), (jnp.abs(J.C).sum(-1) + jnp.abs(J.D).sum(-1)).max(initial=0.0)
        )
        return q + dq, jnp.linalg.norm(R) / F, F, K_inf, jnp.linalg.norm(dq)

    _, step = compile_timed(iteration, q)
    rel, steps = [], []
    F = K_inf = None
    for _ in range(extra_iterations + 1):
        q_next, r, F, K_inf, dq = step(q)
        rel.append(float(r))
        steps.append(float(dq))
        q = q_next
    q_inf = float(jnp.max(jnp.abs(q)))
    return {
        "rel": rel[1:],
        "dq": steps[1:],
        "K_inf": float(K_inf),
        "q_inf": q_inf,
        "F": float(F),
        "estimate": EPS * float(K_inf) * q_inf / float(F),
    }


def _cache_entries(folder) -> int:
    return 0 if folder is None else sum(1 for _ in Path(folder).glob("*"))


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--sizes", type=int, nargs="*", default=[20, 50, 100, 200])
    ap.add_argument("--steps", type=int, default=10_000, help="steps of the long run")
    ap.add_argument("--cache", default=None, help="persistent compilation cache folder")
    ap.add_argument("--no-cache", action="store_true", help="compile everything afresh")
    args = ap.parse_args()
    folder = None if args.no_cache else enable_compilation_cache(args.cache)
    at_start = _cache_entries(folder)
    print(
        f"jax {jax.__version__} on {jax.devices()[0].platform}, {os.cpu_count()} CPU "
        f"cores, load average {os.getloadavg()[0]:.1f}; XLA_FLAGS="
        f"{os.environ.get('XLA_FLAGS', '')!r}"
    )
    print(f"persistent compilation cache: {folder or 'off'} ({at_start} entries at start)")
    print(
        f"HHT alpha = -0.05, dt = {DT:g} s; statics to |R| <= {RTOL:g} F; "
        f"us/el: microseconds per element per Newton iteration\n"
    )
    head = (
        f"{'elements':>8} {'DOFs':>5} | {'static its':>10} {'ms/iter':>8} {'us/el':>6} "
        f"{'|R|/F':>8} | {'HHT ms/step':>11} {'its/step':>8} {'ms/iter':>8} "
        f"{'us/el':>6} | {'compile s: static':>17} {'HHT':>5}"
    )
    print(head)
    print("-" * len(head))
    compile_total = 0.0
    last = None
    for n in args.sizes:
        st = static_case(n)
        dy = dynamic_case(st["model"], st["q"], CHUNK, 3)
        compile_total += st["compile"] + dy["compile"]
        last = (n, st)
        flag = "" if st["status"] == 0 and dy["ok"] else "  (FAILED)"
        print(
            f"{n:>8} {st['n_red']:>5} | {st['iterations']:>10} "
            f"{1e3 * st['per_iter']:>8.2f} {1e6 * st['per_iter'] / n:>6.1f} "
            f"{st['rel_res']:>8.1e} | {1e3 * dy['per_step']:>11.2f} "
            f"{dy['mean_iter']:>8.2f} {1e3 * dy['per_iter']:>8.2f} "
            f"{1e6 * dy['per_iter'] / n:>6.1f} | {st['compile']:>17.1f} "
            f"{dy['compile']:>5.1f}{flag}"
        )

    n, st = last
    m = st["model"]
    print(
        f"\n{n}-element static solve: |R|/F = {st['rel_res']:.1e} after "
        f"{st['iterations']} Newton iterations ({1e3 * st['solve']:.1f} ms), stopped by "
        + (
            "the residual test |R| <= 1e-10 F"
            if st["rel_res"] <= RTOL
            else "the round-off step test (last correction below xtol), not the residual test"
        )
    )
    fl = floor_study(m, st["q"])
    print(
        f"  continued {len(fl['rel'])} more iterations with no stopping test: |R|/F "
        f"between {min(fl['rel']):.1e} and {max(fl['rel']):.1e}, corrections "
        f"|dq| <= {max(fl['dq']):.1e} mm (round-off)"
    )
    print(
        f"  round-off floor estimate eps |K|_inf |q|_inf / F = {EPS:.1e} x "
        f"{fl['K_inf']:.2e} N/mm x {fl['q_inf']:.2e} mm / {fl['F']:.3f} N = "
        f"{fl['estimate']:.1e}"
    )

    dy = dynamic_case(m, st["q"], args.steps, 1)
    compile_total += dy["compile"]
    right = st["nodes"]["right"]  # the actuated body end
    t_end = float(dy["final"].t)
    s_end = 20.0 * math.sin(math.pi * t_end / 20.0) ** 2
    print(
        f"\n{args.steps} HHT steps ({n} elements, one compiled lax.scan, dt = {DT:g} s): "
        f"{dy['run']:.1f} s wall, {1e3 * dy['per_step']:.2f} ms/step, Newton iterations "
        f"mean {dy['mean_iter']:.2f} max {dy['max_iter']}, all converged: {dy['ok']}; "
        f"compile {dy['compile']:.1f} s"
    )
    print(
        f"  t_end = {t_end:.3f} s, actuated end x displacement "
        f"{float(dy['final'].u[right, 0]):.6f} mm (prescribed -s(t) = {-s_end:.6f} mm)"
    )
    print(
        f"\ncompile total {compile_total:.1f} s; cache entries now "
        f"{_cache_entries(folder)} (a second process run loads them); load average "
        f"{os.getloadavg()[0]:.1f}"
    )


if __name__ == "__main__":
    main()
