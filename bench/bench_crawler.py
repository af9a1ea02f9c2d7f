"""Benchmark of the FE crawler: the paper scenario, wall time, steps, iterations.

Runs ``bristlecrawler.crawler.run`` on a shipped scenario (default ``paper``)
with optional ``--set section.key=value`` overrides (as in ``bristlecrawler simulate``),
twice by default: the first run includes compilation, the second (same process, programs
cached) does not. Prints a table (wall times per step and per iteration of the whole run)
and, per run, the stroke's own time (step 2 alone: no compilation, gravity step or modal
analysis); nothing is asserted. A run that fails is reported with
the solver's message and the simulated time it reached.

    python bench/bench_crawler.py [--scenario paper] [--cycles 5] [--set bristle.elements=20]
                                  [--repeat 2] [--compile-threads 4]

Targets (a 2-core machine): the paper scenario, 5 cycles (100 s simulated), at converged
resolution in <= 30 s of wall time after compilation, compilation <= 60 s. For a cold
start, run with ``BRISTLECRAWLER_NO_JAX_CACHE=1``; ``--compile-threads 1`` compiles the
programs one after the other, for comparison.
"""

from __future__ import annotations

import argparse
import time


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scenario", default="paper")
    ap.add_argument("--cycles", type=int, default=None)
    ap.add_argument("--set", dest="sets", action="append", default=[])
    ap.add_argument("--repeat", type=int, default=2)
    ap.add_argument("--compile-threads", type=int, default=4)
    a = ap.parse_args()

    from bristlecrawler.crawler import RunOptions, run
    from bristlecrawler.errors import SolverError
    from bristlecrawler.fe import enable_compilation_cache
    from bristlecrawler.jobs.simulate import summarize
    from bristlecrawler.scenario.convert import to_spec
    from bristlecrawler.scenario.load import apply_overrides, load_scenario

    enable_compilation_cache()
    sc = load_scenario(a.scenario)
    sets = list(a.sets)
    if a.cycles is not None:
        sets.append(f"actuation.cycles={a.cycles}")
    sc = apply_overrides(sc, sets)
    print(
        f"scenario {sc.name}: {sc.actuation.cycles} cycles of {sc.actuation.period} s, "
        f"{sc.bristle.elements} elements per bristle, contact {sc.contact.nodes}"
        f" (surface {sc.contact.surface}), overrides {sets or 'none'}"
    )
    head = (
        f"{'run':>4} {'wall s':>8} {'sim s':>7} {'steps':>7} {'newton':>8} "
        f"{'ms/step':>8} {'ms/iter':>8} {'advance mm':>11} {'work mJ':>9} {'balance':>9}"
    )
    print(head)
    print("-" * len(head))
    walls = []
    for r in range(a.repeat):
        t0 = time.perf_counter()
        try:
            h = run(to_spec(sc), options=RunOptions(compile_threads=a.compile_threads))
            failed = None
        except SolverError as e:
            h, failed = getattr(e, "partial", None), str(e)
        wall = time.perf_counter() - t0
        walls.append(wall)
        if h is None:
            print(f"{r + 1:>4} failed before the stroke: {failed}")
            break
        st = h.stats
        steps, its = max(st["steps"], 1), max(st["newton_iterations"], 1)
        s = summarize(h, sc)
        print(
            f"{r + 1:>4} {wall:8.1f} {h.t[-1]:7.2f} {steps:7d} {its:8d} "
            f"{1e3 * wall / steps:8.2f} {1e3 * wall / its:8.3f} "
            f"{s['net_advance_mm']:11.3f} {s['work_mJ']:9.3f} "
            f"{s['energy_balance_rel_error']:9.2e}"
        )
        per = ", ".join(f"{x:.3f}" for x in s["advance_per_cycle_mm"])
        stroke, stroke_its = st["stroke_wall_time_s"], max(st["stroke_newton_iterations"], 1)
        print(
            f"     per cycle (mm): {per}; programs loaded or compiled in "
            f"{s['compile_time_s']:.1f} s ({a.compile_threads} threads)"
        )
        print(
            f"     stroke alone (step 2): {stroke:.1f} s, {stroke_its} iterations, "
            f"{1e3 * stroke / steps:.2f} ms/step, {1e3 * stroke / stroke_its:.3f} ms/iter"
        )
        if failed:
            print(f"     FAILED: {failed}")
            break
    if len(walls) >= 2:
        print(f"compilation (first run minus second): {walls[0] - walls[1]:.1f} s")


if __name__ == "__main__":
    main()
