"""Benchmark of ``bristlecrawler sweep``: throughput and the cost of the sweep machinery.

Run: ``python bench/bench_sweep.py [--fe] [--workers 2]``. Prints a table; nothing is
asserted. Rows:

* 10^6 reduced closed-form designs end to end (study file to ``study.zarr``, local
  cluster, no figures), and the part of it spent checking the designs;
* the sweep's overhead per design: reduced exact-solver designs, one task each, one
  worker, against the same designs called bare in one process (cluster start apart);
* with ``--fe``: FE designs per hour (two-cycle runs of the paper scenario at four
  inclinations) with 1 and with 2 workers, each worker compiling once (the JAX
  persistent cache off, so a cold start is measured).
"""

from __future__ import annotations

import argparse
import os
import tempfile
import time
from pathlib import Path

MILLION = """
name = "million"
model = "reduced"
[axes]
s_max = {{ linspace = [1.0, 40.0, 1000] }}
fp = {{ linspace = [0.05, 2.0, {n}] }}
"""

OVERHEAD = """
name = "overhead"
model = "reduced"
reduced_solver = "exact"
chunk = 1
[set]
bristles = 3
cycles = 1
samples_per_cycle = 200
[axes]
s_max = {{ linspace = [5.0, 40.0, {n}] }}
"""

FE = """
name = "fe-bench"
model = "fe"
base = "paper"
[set]
"actuation.cycles" = 2
"output.vtk" = false
"output.figures" = false
"output.animation" = false
[axes]
"bristle.alpha_deg" = [30.0, 40.0, 45.0, 50.0]
"""


def _study(folder: Path, name: str, text: str) -> str:
    path = folder / f"{name}.toml"
    path.write_text(text)
    return str(path)


def _sweep(study: str, out: Path, workers: int) -> tuple[float, dict]:
    from bristlecrawler.studies import SweepOptions, run_sweep

    t0 = time.perf_counter()
    summary = run_sweep(
        study, SweepOptions(out=out, workers=workers, figures=False, progress=False)
    )
    return time.perf_counter() - t0, summary


def million(folder: Path, workers: int) -> list[tuple]:
    from bristlecrawler.studies import plan

    study = _study(folder, "million", MILLION.format(n=1000))
    t0 = time.perf_counter()
    n = plan(study).designs.n
    t_plan = time.perf_counter() - t0
    wall, summary = _sweep(study, folder / "million", workers)
    assert summary["designs_done"] == n
    return [
        ("reduced closed form, end to end", f"{n:.0e} designs, {workers} workers", wall, n),
        ("  of which: expand and check the designs", f"{n:.0e} designs", t_plan, n),
    ]


def overhead(folder: Path, n: int = 200) -> list[tuple]:
    import numpy as np

    from bristlecrawler.studies import evaluate_reduced, plan
    from bristlecrawler.studies.execute import connect

    study = _study(folder, "overhead", OVERHEAD.format(n=n))
    p = plan(study)
    t0 = time.perf_counter()
    for i in range(n):
        evaluate_reduced(p.base.config | p.designs.overrides(i))
    bare = time.perf_counter() - t0
    t0 = time.perf_counter()
    client, cluster = connect(None, 1)
    client.close()
    cluster.close()
    start = time.perf_counter() - t0
    wall, _ = _sweep(study, folder / "overhead", 1)
    per = (wall - start - bare) / n
    return [
        ("bare call, reduced exact solver", f"{n} designs, 1 process", bare / n, 1),
        ("sweep, same designs, one task each", f"{n} tasks, 1 worker", wall / n, 1),
        ("  local cluster start and stop", "1 worker", start, 1),
        ("  overhead per design (sweep - start - bare)", "", float(np.maximum(per, 0.0)), 1),
    ]


def fe(folder: Path) -> None:
    os.environ["BRISTLECRAWLER_NO_JAX_CACHE"] = "1"
    study = _study(folder, "fe", FE)
    for workers in (1, 2):
        wall, summary = _sweep(study, folder / f"fe{workers}", workers)
        done = summary["designs_done"]
        size = f"{done}/{summary['designs_total']} designs, {workers} workers"
        _print([("FE paper scenario, 2 cycles, cold workers", size, wall, done)])


def _print(rows: list[tuple]) -> None:
    for case, size, t, n in rows:
        if t is None:
            print(f"{case:48s} {size:34s} {'-':>10s} {'-':>12s}", flush=True)
            continue
        rate = f"{3600 * n / t:12.3g}" if n and t > 0 and case.startswith("FE") else ""
        print(f"{case:48s} {size:34s} {t:10.3g} {rate:>12s}", flush=True)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--fe", action="store_true", help="also the FE designs per hour (minutes)")
    ap.add_argument("--workers", type=int, default=os.cpu_count() or 1)
    args = ap.parse_args()
    # Rows are printed as they come: a run stopped half way still reports what it measured.
    print(f"{'case':48s} {'size':34s} {'time (s)':>10s} {'per hour':>12s}", flush=True)
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        _print(million(folder, args.workers))
        _print(overhead(folder))
        if args.fe:
            fe(folder)
        else:
            _print([("FE designs per hour", "not measured (--fe)", None, 0)])


if __name__ == "__main__":
    main()
