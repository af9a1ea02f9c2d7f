"""Benchmark of the virtual drag test: the paper's bristle dragged over 10 groove pitches.

The first run compiles the programs (a drag of one pitch); the timed runs then drag the
bristle along the grain over ``--pitches`` pitches (default 10, 20 mm on the paper's 2 mm
grooves) at 2 mm/s, with the programs compiled. Prints a table: wall time, steps, Newton
iterations, per-step and per-iteration cost, F_p; nothing is asserted.

    python bench/bench_drag.py [--pitches 10] [--repeat 2] [--scenario paper]

Target (2-core machine): 10 pitches within 30 s after compilation.
"""

from __future__ import annotations

import argparse
import time


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scenario", default="paper")
    ap.add_argument("--pitches", type=int, default=10)
    ap.add_argument("--repeat", type=int, default=2)
    a = ap.parse_args()

    from bristlecrawler.crawler.drag import DragTest, drag_test
    from bristlecrawler.fe import enable_compilation_cache
    from bristlecrawler.scenario import load_spec

    enable_compilation_cache()
    spec = load_spec(a.scenario)
    pitch = spec.substrate.period
    t0 = time.perf_counter()
    drag_test(spec, DragTest(direction="along", distance=pitch))
    print(f"scenario {a.scenario}: pitch {pitch:g} mm; first run (compiles, 1 pitch) "
          f"{time.perf_counter() - t0:.1f} s")  # fmt: skip
    head = (
        f"{'run':>4} {'pitches':>8} {'wall s':>8} {'steps':>7} {'newton':>8} "
        f"{'ms/step':>8} {'ms/iter':>8} {'F_p N':>8} {'balance':>8}"
    )
    print(head)
    print("-" * len(head))
    test = DragTest(direction="along", distance=a.pitches * pitch)
    for r in range(a.repeat):
        t0 = time.perf_counter()
        s = drag_test(spec, test).summary()
        wall = time.perf_counter() - t0
        steps, its = s["steps"], s["newton_iterations"]
        print(
            f"{r + 1:>4} {a.pitches:>8} {wall:>8.1f} {steps:>7} {its:>8} "
            f"{1e3 * wall / steps:>8.2f} {1e3 * wall / max(its, 1):>8.3f} "
            f"{s['fp_N']:>8.4f} {s['energy_balance_rel_error']:>8.1e}",
            flush=True,
        )


if __name__ == "__main__":
    main()
