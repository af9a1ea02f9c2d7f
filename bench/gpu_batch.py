"""Batched FE designs on a GPU: wall time, designs per minute and GPU memory per batch width.

Designs of the ``paper`` design (five cycles by default) on an alpha x mu grid, one
:func:`crawler.run_batch` per width B (default 64, 1024, 256), each B its own compiled
program. Prints one row per width as it ends: compilation, the batched gravity step, the
batched stroke, the whole batch (building the designs and their modal analyses
included), designs per minute (compilation left out), utilisation, the device's peak
memory, the stroke's time per batched Newton iteration and the spread of the designs' net
advance. A width that runs past its ``--budgets`` (seconds; what a width leaves goes to
the next) is stopped at its next return to the host and reported as stopped, with the
simulated time its slowest design reached. ``--trials`` chooses how Newton's line
search makes its trials in the batch (:class:`crawler.RunOptions` ``batch_trials``; the
same results either way). Needs a JAX with CUDA (on a CPU it says so
and stops, unless ``--cpu``). Builds the designs from :meth:`CrawlerSpec.paper` (no
scenario file, so no pydantic needed).

    python bench/gpu_batch.py [--widths 1024 64 256] [--cycles 5] [--elements 20]
                              [--budgets 330 80 90] [--trials auto] [--cpu]
"""

from __future__ import annotations

import argparse
import dataclasses
import sys
import time

import numpy as np


class Stopped(Exception):
    """A width ran past its share of the budget."""


def designs(width: int, cycles: int, elements: int | None):
    from bristlecrawler.crawler import CrawlerSpec

    sys.path.insert(0, __file__.rsplit("/", 1)[0])
    from bench_batch import grid

    base = CrawlerSpec.paper()
    base = dataclasses.replace(base, actuation=dataclasses.replace(base.actuation, cycles=cycles))
    if elements is not None:
        base = base.replace_bristles(elements=elements)
    return grid(base, width)


def watch(deadline: float, t_start: float, state: dict):
    """A progress callback that prints each return to the host and stops past ``deadline``."""

    def on_progress(p) -> None:
        state["last"] = p
        now = time.perf_counter()
        print(
            f"    {now - t_start:7.1f} s  {p.stage:<13} slowest design at t = {p.t:7.3f} "
            f"of {p.t_end:7.3f} s",
            flush=True,
        )
        if now > deadline:
            raise Stopped

    return on_progress


def one_width(width: int, a, deadline: float, device) -> None:
    from bristlecrawler.crawler import RunOptions, run_batch

    t0 = time.perf_counter()
    specs = designs(width, a.cycles, a.elements)
    state: dict = {}
    try:
        options = RunOptions(batch_trials=a.trials)
        b = run_batch(specs, options=options, on_progress=watch(deadline, t0, state))
    except Stopped:
        p = state["last"]
        peak = (device.memory_stats() or {}).get("peak_bytes_in_use", float("nan")) / 2**30
        print(
            f"{width:6d} stopped after {time.perf_counter() - t0:.1f} s in the {p.stage}, "
            f"slowest design at t = {p.t:.3f} of {p.t_end:.3f} s, {p.iterations} Newton "
            f"iterations of the designs; peak {peak:.2f} GiB",
            flush=True,
        )
        return
    except Exception as exc:  # a benchmark row, not a crash: the next width still runs
        print(f"{width:6d} failed after {time.perf_counter() - t0:.1f} s: {exc!r}", flush=True)
        return
    wall = time.perf_counter() - t0
    s = b.stats
    failed = sum(e is not None for e in b.errors)
    rate = 60 * (width - failed) / (wall - s["compile_time_s"])
    peak = (device.memory_stats() or {}).get("peak_bytes_in_use", float("nan")) / 2**30
    adv = np.array([h.net_advance for h in b.histories if h is not None])
    print(
        f"{width:6d} {s['compile_time_s']:10.1f} {s['settle_wall_time_s']:9.1f} "
        f"{s['stroke_wall_time_s']:9.1f} {wall:8.1f} {rate:12.1f} {s['utilisation']:11.2f} "
        f"{failed:7d} {peak:9.2f} {1e3 * s['stroke_wall_time_s'] / s['batch_iterations']:8.2f}"
        f"   advance {adv.min():.2f}-{adv.max():.2f} mm",
        flush=True,
    )
    print(
        "       outside the batched program: "
        + ", ".join(
            f"{k} {s[k + '_wall_time_s']:.1f} s" for k in ("prepare", "modal", "histories")
        ),
        flush=True,
    )
    for e in {e for e in b.errors if e is not None}:
        print(f"    failure: {e}")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--widths", type=int, nargs="+", default=[1024, 64, 256])
    ap.add_argument("--cycles", type=int, default=5)
    ap.add_argument("--elements", type=int, default=None)
    ap.add_argument(
        "--budgets",
        type=float,
        nargs="+",
        default=[330.0, 80.0, 90.0],
        help="seconds for each width (what one leaves goes to the next)",
    )
    ap.add_argument("--trials", choices=["auto", "sequential", "parallel"], default="auto")
    ap.add_argument("--cpu", action="store_true", help="run on a CPU too (to try the script)")
    a = ap.parse_args()

    import jax

    from bristlecrawler.fe import enable_compilation_cache

    if jax.default_backend() != "gpu" and not a.cpu:
        print(f"no GPU: JAX computes on {jax.default_backend()}")
        return
    device = jax.devices()[0]
    enable_compilation_cache()
    print(
        f"{device.device_kind}; JAX {jax.__version__}; paper, {a.cycles} cycles, "
        f"elements per bristle {a.elements or 'as the paper'}; line-search trials {a.trials}"
    )
    head = (
        f"{'B':>6} {'compile s':>10} {'settle s':>9} {'stroke s':>9} {'wall s':>8} "
        f"{'designs/min':>12} {'utilisation':>11} {'failed':>7} "
        f"{'peak GiB':>9} {'ms/it':>8}"
    )
    print(head + "\n" + "-" * len(head), flush=True)
    if len(a.budgets) != len(a.widths):
        ap.error("give one budget per width")
    deadline = time.perf_counter()
    for width, budget in zip(a.widths, a.budgets, strict=True):
        deadline += budget
        one_width(width, a, deadline, device)


if __name__ == "__main__":
    main()
