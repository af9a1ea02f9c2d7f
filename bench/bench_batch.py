"""Benchmark of batched FE designs on the CPU: designs per hour against single runs.

Designs of the ``paper`` scenario (two cycles by default) on an alpha x mu grid. First a
few single runs with the host loop (:func:`crawler.run`, the CPU default; the first one
compiles and is not timed), then for each batch width B one :func:`crawler.run_batch` of
B designs of the grid, whose compilation (or load from the persistent cache) is reported
apart. Prints one row per case as it ends: wall time, designs per hour (compilation left
out), utilisation (the designs' own Newton iterations over B x the batch's iterations),
the batch's iterations and its longest design's own, and the largest difference in net
advance from the single runs of the same designs.

    python bench/bench_batch.py [--widths 1 2 4 8 16] [--cycles 2] [--singles 2]
                                [--set bristle.elements=20]
"""

from __future__ import annotations

import argparse
import dataclasses
import os
import time

import numpy as np


def grid(base, n: int):
    """``n`` designs of an alpha x mu grid around the paper's design (alpha 45-55 degrees,
    mu 0.55-0.8), the paper's first."""
    side = int(np.ceil(np.sqrt(n)))
    alphas, mus = np.linspace(45.0, 55.0, side), np.linspace(0.65, 0.8, side)
    out = []
    for a in alphas:
        for mu in mus:
            spec = base.replace_bristles(alpha_deg=float(a))
            out.append(
                dataclasses.replace(spec, contact=dataclasses.replace(spec.contact, mu=float(mu)))
            )
    return out[:n]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--widths", type=int, nargs="+", default=[1, 2, 4, 8, 16])
    ap.add_argument("--cycles", type=int, default=2)
    ap.add_argument("--singles", type=int, default=2)
    ap.add_argument("--set", dest="sets", action="append", default=[])
    a = ap.parse_args()

    from bristlecrawler.crawler import run, run_batch
    from bristlecrawler.errors import SolverError
    from bristlecrawler.fe import enable_compilation_cache
    from bristlecrawler.scenario.convert import to_spec
    from bristlecrawler.scenario.load import apply_overrides, load_scenario

    enable_compilation_cache()
    sc = apply_overrides(load_scenario("paper"), [*a.sets, f"actuation.cycles={a.cycles}"])
    base = to_spec(sc)
    designs = grid(base, max(max(a.widths), a.singles))
    print(
        f"paper, {a.cycles} cycles, {sc.bristle.elements} elements per bristle; "
        f"load average {os.getloadavg()[0]:.2f}"
    )
    head = (
        f"{'case':>15} {'wall s':>8} {'compile s':>10} {'designs/h':>10} "
        f"{'utilisation':>11} {'batch its':>10} {'longest':>8} {'max |d advance| mm':>19} "
        f"{'load':>5}"
    )
    print(head + "\n" + "-" * len(head), flush=True)
    t0 = time.perf_counter()
    run(designs[0])  # compiles the host loop's programs
    print(f"{'single, compile':>15} {time.perf_counter() - t0:8.1f}", flush=True)
    single = {}
    for i in range(a.singles):
        t0 = time.perf_counter()
        try:
            single[i] = run(designs[i]).net_advance
        except SolverError as exc:
            print(f"single {i} failed: {exc}")
            continue
        wall = time.perf_counter() - t0
        print(
            f"{'single ' + str(i):>15} {wall:8.1f} {'-':>10} {3600 / wall:10.0f} {'-':>11} "
            f"{'-':>10} {'-':>8} {'-':>19} {os.getloadavg()[0]:5.2f}",
            flush=True,
        )
    for width in a.widths:
        t0 = time.perf_counter()
        b = run_batch(designs[:width])
        wall = time.perf_counter() - t0
        s = b.stats
        diffs = [
            abs(b.histories[i].net_advance - single[i])
            for i in single
            if i < width and b.histories[i] is not None
        ]
        failed = sum(e is not None for e in b.errors)
        own = [h.stats["stroke_newton_iterations"] for h in b.histories if h is not None]
        longest = max(own, default=0)
        rate = 3600 * (width - failed) / (wall - s["compile_time_s"])
        print(
            f"{'batch B=' + str(width):>15} {wall:8.1f} {s['compile_time_s']:10.1f} "
            f"{rate:10.0f} {s['utilisation']:11.2f} {s['batch_iterations']:10d} "
            f"{longest:8d} "
            f"{(max(diffs) if diffs else float('nan')):19.2e} {os.getloadavg()[0]:5.2f}"
            + (f"  ({failed} failed)" if failed else ""),
            flush=True,
        )


if __name__ == "__main__":
    main()
