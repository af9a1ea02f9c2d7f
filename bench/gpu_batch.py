"""Batched FE designs on a GPU: wall time, designs per minute and GPU memory per batch width.

Designs of the ``paper`` scenario (five cycles by default) on an alpha x mu grid, one
:func:`crawler.run_batch` per width B (default 64, 256, 1024), each B its own compiled
program. Prints one row per width as it ends: compilation, the batched stroke alone, the
whole batch (the per-design gravity steps and modal analyses included), designs per
minute (compilation left out), utilisation and the device's peak memory. Needs a JAX
with CUDA; on a CPU it says so and stops.

    python bench/gpu_batch.py [--widths 64 256 1024] [--cycles 5]
"""

from __future__ import annotations

import argparse
import sys
import time


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--widths", type=int, nargs="+", default=[64, 256, 1024])
    ap.add_argument("--cycles", type=int, default=5)
    ap.add_argument("--set", dest="sets", action="append", default=[])
    a = ap.parse_args()

    import jax

    from bristlecrawler.crawler import run_batch
    from bristlecrawler.fe import enable_compilation_cache
    from bristlecrawler.scenario.convert import to_spec
    from bristlecrawler.scenario.load import apply_overrides, load_scenario

    sys.path.insert(0, __file__.rsplit("/", 1)[0])
    from bench_batch import grid

    if jax.default_backend() != "gpu":
        print(f"no GPU: JAX computes on {jax.default_backend()}")
        return
    device = jax.devices()[0]
    enable_compilation_cache()
    sc = apply_overrides(load_scenario("paper"), [*a.sets, f"actuation.cycles={a.cycles}"])
    base = to_spec(sc)
    print(f"{device.device_kind}; paper, {a.cycles} cycles, {sc.bristle.elements} elements")
    head = (
        f"{'B':>6} {'compile s':>10} {'stroke s':>9} {'wall s':>8} {'designs/min':>12} "
        f"{'utilisation':>11} {'failed':>7} {'peak GiB':>9}"
    )
    print(head + "\n" + "-" * len(head), flush=True)
    for width in a.widths:
        t0 = time.perf_counter()
        b = run_batch(grid(base, width))
        wall = time.perf_counter() - t0
        s = b.stats
        failed = sum(e is not None for e in b.errors)
        rate = 60 * (width - failed) / (wall - s["compile_time_s"])
        peak = (device.memory_stats() or {}).get("peak_bytes_in_use", float("nan")) / 2**30
        print(
            f"{width:6d} {s['compile_time_s']:10.1f} {s['stroke_wall_time_s']:9.1f} "
            f"{wall:8.1f} {rate:12.1f} {s['utilisation']:11.2f} {failed:7d} {peak:9.2f}",
            flush=True,
        )


if __name__ == "__main__":
    main()
