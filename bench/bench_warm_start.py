"""Benchmark of a cold and a warm start: the time until an FE run starts stepping.

Runs the same short run (a scenario, one short stroke) in fresh processes on one cache
folder: first on an empty folder (a cold start: every program traced and compiled), then
``--warm`` times again (each process loads the stored programs). Prints, per process, its
wall time to import and build, the run's compile (or load) time, the stroke's own time and
the run's advance, which must agree between cold and warm. Nothing is asserted.

    python bench/bench_warm_start.py [--scenario paper] [--set bristle.elements=6]
                                     [--warm 2] [--cache DIR]

``--cache DIR`` keeps the folder (default: a fresh temporary one, removed afterwards).
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time

CHILD = """
import json, sys, time
t0 = time.perf_counter()
from bristlecrawler.crawler import run
from bristlecrawler.scenario.convert import to_spec
from bristlecrawler.scenario.load import apply_overrides, load_scenario

sc = apply_overrides(load_scenario(sys.argv[1]), sys.argv[2:])
spec = to_spec(sc)
t1 = time.perf_counter()
h = run(spec)
t2 = time.perf_counter()
print(json.dumps({
    "build_s": t1 - t0,
    "run_s": t2 - t1,
    "compile_s": h.stats["compile_time_s"],
    "stroke_s": h.stats.get("stroke_wall_time_s", float("nan")),
    "advance_mm": float(h.net_advance),
}))
"""


def _child(folder: str, scenario: str, sets: list[str]) -> dict:
    env = dict(os.environ, BRISTLECRAWLER_JAX_CACHE=folder)
    env.pop("BRISTLECRAWLER_NO_JAX_CACHE", None)
    t0 = time.perf_counter()
    done = subprocess.run(
        [sys.executable, "-c", CHILD, scenario, *sets],
        env=env,
        capture_output=True,
        text=True,
    )
    wall = time.perf_counter() - t0
    if done.returncode != 0:
        raise SystemExit(f"run failed:\n{done.stderr[-2000:]}")
    out = json.loads(done.stdout.strip().splitlines()[-1])
    out["wall_s"] = wall
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scenario", default="paper")
    ap.add_argument(
        "--set",
        dest="sets",
        action="append",
        default=None,
        help="scenario overrides (default: one 6 mm stroke of 4 s, 6 elements per bristle)",
    )
    ap.add_argument("--warm", type=int, default=2)
    ap.add_argument("--cache", default=None)
    a = ap.parse_args()
    sets = a.sets or [
        "bristle.elements=6",
        "actuation.cycles=1",
        "actuation.s_max=6.0",
        "actuation.period=4.0",
    ]
    folder = a.cache or tempfile.mkdtemp(prefix="bristlecrawler-bench-cache-")
    print(f"scenario {a.scenario}, overrides {sets}, cache {folder}")
    head = (
        f"{'process':>8} {'wall s':>8} {'build s':>8} {'compile/load s':>15} "
        f"{'stroke s':>9} {'advance mm':>12}"
    )
    print(head)
    print("-" * len(head))
    try:
        for i in range(1 + a.warm):
            r = _child(folder, a.scenario, sets)
            name = "cold" if i == 0 else f"warm {i}"
            print(
                f"{name:>8} {r['wall_s']:8.1f} {r['build_s']:8.1f} {r['compile_s']:15.1f} "
                f"{r['stroke_s']:9.1f} {r['advance_mm']:12.6f}",
                flush=True,
            )
    finally:
        if a.cache is None:
            shutil.rmtree(folder, ignore_errors=True)


if __name__ == "__main__":
    main()
