"""Benchmark of the bristled model (elastic bristles on the grooves, no FE): one design,
and a batch of two-bristle designs.

Run: ``python bench/bench_bristled.py [--batch 40] [--ds 0.1] [--reference DIR]``. Prints a
table; nothing is asserted. Each design is two cycles of a breathing stroke (8 to 20 mm)
on grooves of 1.5 to 4 mm pitch at 30 to 60 degrees. Targets: at least 100 two-cycle
designs per second in a batch, under 0.1 s for one design. Both wall and process (CPU)
time are given: on a shared machine the wall time is the load's. ``--reference DIR``
runs the same cases on the package in ``DIR/src`` too (another checkout, e.g. an older
revision: ``git worktree add /tmp/old <rev>``) and prints its rows beside these.
"""

from __future__ import annotations

import argparse
import itertools
import json
import os
import subprocess
import sys
import time

from bristlecrawler.reduced.bristled import (
    BristledDesign,
    GroovedSurface,
    RunOptions,
    TaperedBristle,
    run,
)


def designs(n: int) -> list[BristledDesign]:
    """``n`` two-bristle designs over inclination x pitch x stroke."""
    grid = itertools.product((30.0, 45.0, 60.0), (1.5, 2.0, 3.0, 4.0), (8.0, 14.0, 20.0))
    out = []
    for alpha, pitch, stroke in itertools.islice(itertools.cycle(grid), n):
        out.append(
            BristledDesign.uniform(
                2,
                bristle=TaperedBristle(alpha_deg=alpha),
                surface=GroovedSurface(pitch=pitch),
                s_max=stroke,
            )
        )
    return out


def timed(fn):
    t0, c0 = time.perf_counter(), time.process_time()
    out = fn()
    return out, time.perf_counter() - t0, time.process_time() - c0


def measure(batch: int, ds: float) -> list[tuple[str, int, float, float]]:
    """(case, designs, wall s, cpu s) of one design and of a batch."""
    opts = RunOptions(ds=ds)
    run(designs(1), cycles=1, options=RunOptions(ds=2.0))  # calibration and paths cached
    rows = []
    one = [BristledDesign.uniform(2)]
    _, wall, cpu = timed(lambda: run(one, cycles=2, options=opts))
    rows.append(("one design (paper's)", 1, wall, cpu))
    many = designs(batch)
    for d in many:  # the tip paths, once per substrate and bristle (cached)
        run([d], cycles=1, options=RunOptions(ds=4.0))
    r, wall, cpu = timed(lambda: run(many, cycles=2, options=opts))
    rows.append((f"batch, {int(r.ok.sum())} settled", len(many), wall, cpu))
    return rows


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__)
    p.add_argument("--batch", type=int, default=40, help="designs in the batch")
    p.add_argument("--ds", type=float, default=RunOptions.ds, help="stroke step, mm")
    p.add_argument("--reference", help="a checkout whose src/ to run the same cases on")
    p.add_argument("--json", action="store_true", help=argparse.SUPPRESS)
    args = p.parse_args()
    rows = [("this", *row) for row in measure(args.batch, args.ds)]
    if args.json:
        print(json.dumps(rows))
        return
    if args.reference:
        env = dict(os.environ, PYTHONPATH=os.path.join(args.reference, "src"))
        cmd = [sys.executable, __file__, "--json", "--batch", str(args.batch)]
        out = subprocess.run(
            [*cmd, "--ds", str(args.ds)], env=env, capture_output=True, text=True, check=True
        )
        rows += [("reference", *row[1:]) for row in json.loads(out.stdout.splitlines()[-1])]
    print(
        f"{'code':<11}{'case':<28}{'designs':>8}{'wall s':>10}{'cpu s':>10}"
        f"{'designs/s':>11}{'cpu s/design':>14}"
    )
    for code, name, n, wall, cpu in rows:
        print(
            f"{code:<11}{name:<28}{n:>8}{wall:>10.2f}{cpu:>10.2f}{n / wall:>11.3f}{cpu / n:>14.3f}"
        )


if __name__ == "__main__":
    main()
