"""Benchmark of the reduced model: closed form over many designs, exact solver.

Run: ``python bench/bench_reduced.py``. Prints a table; nothing is asserted.
Targets (2-core machine): closed form over 1e6 designs < 1 s; solver, two
bristles, 5 cycles x 1e4 samples < 0.2 s; ten bristles < 2 s.
"""

from __future__ import annotations

import time

import numpy as np

from bristlecrawler.reduced import ReducedCrawler, Sin2Stroke, closed_form, peristaltic, simulate


def best_of(fn, repeat: int = 5) -> float:
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return min(times)


def main() -> None:
    rows = []
    rng = np.random.default_rng(0)
    n = 1_000_000
    s, c, k = rng.uniform(1, 40, n), rng.uniform(0.01, 25, n), rng.uniform(0.1, 2, n)

    def cf():
        closed_form.net_advance(s, c, 5)
        closed_form.work(s, c * k, k, 5)

    rows.append(("closed form: advance + work", "1e6 designs", best_of(cf), n))
    for nb, smax in ((2, 20.0), (10, 9.0)):
        crawler = ReducedCrawler.uniform(nb)
        st = Sin2Stroke(smax, 20.0)
        res = simulate(crawler, st, 5, 10_000)
        t = best_of(lambda crawler=crawler, st=st: simulate(crawler, st, 5, 10_000))
        rows.append(
            (
                f"exact solver, {nb} bristles, breathing",
                f"5 cycles x 1e4 samples, {len(res.events)} events",
                t,
                res.t.size,
            )
        )
    crawler = ReducedCrawler.uniform(10, length=200.0)
    gait = peristaltic(Sin2Stroke(15.0, 20.0), 9, 2.0)
    res = simulate(crawler, gait, 5, 10_000)
    t = best_of(lambda: simulate(crawler, gait, 5, 10_000))
    rows.append(
        (
            "exact solver, 10 bristles, peristaltic",
            f"5 cycles x 1e4 samples, {len(res.events)} events",
            t,
            res.t.size,
        )
    )

    print(f"{'case':42s} {'size':34s} {'time (s)':>9s} {'per item (us)':>14s}")
    for name, size, t, items in rows:
        print(f"{name:42s} {size:34s} {t:9.4f} {1e6 * t / items:14.3f}")


if __name__ == "__main__":
    main()
