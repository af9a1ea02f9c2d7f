"""Benchmark of the bristled model (elastic bristles on the grooves, no FE): one design,
and batches of two-bristle designs.

Run: ``python bench/bench_bristled.py [--batch 1,12,48,200] [--ds 0.1] [--reference DIR]``.
Prints a table; nothing is asserted. Each design is two cycles of a breathing stroke on
grooves of 1.5 to 4 mm pitch at 30 to 60 degrees; the strokes (8 to 20 mm) differ from
design to design, so that no two designs of a batch are the same and a larger batch
does not gain by playing copies in step. Targets: at least 100 two-cycle designs per
second in a batch, under 0.1 s for one design. Both wall and process (CPU) time are
given: on a shared machine the wall time is the load's. ``--reference DIR``
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
    """``n`` two-bristle designs over inclination x pitch (12 pairs, in turn) x stroke
    (8 to 20 mm, spread by the golden ratio: no two alike)."""
    grid = list(itertools.product((30.0, 45.0, 60.0), (1.5, 2.0, 3.0, 4.0)))
    out = []
    for k in range(n):
        alpha, pitch = grid[k % len(grid)]
        stroke = 8.0 + 12.0 * ((k * 0.6180339887498949) % 1.0)
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


def measure(batches, ds: float) -> list[tuple[str, int, float, float]]:
    """(case, designs, wall s, cpu s) of one design and of each batch size."""
    opts = RunOptions(ds=ds)
    run(designs(1), cycles=1, options=RunOptions(ds=2.0))  # calibration and paths cached
    rows = []
    one = [BristledDesign.uniform(2)]
    _, wall, cpu = timed(lambda: run(one, cycles=2, options=opts))
    rows.append(("one design (paper's)", 1, wall, cpu))
    for d in designs(12):  # the tip paths, once per substrate and bristle (cached)
        run([d], cycles=1, options=RunOptions(ds=4.0))
    for batch in batches:
        many = designs(batch)
        r, wall, cpu = timed(lambda many=many: run(many, cycles=2, options=opts))
        rows.append((f"batch, {int(r.ok.sum())} settled", len(many), wall, cpu))
    return rows


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__)
    p.add_argument("--batch", default="12,48,200", help="designs in each batch, comma-separated")
    p.add_argument("--ds", type=float, default=RunOptions.ds, help="stroke step, mm")
    p.add_argument("--reference", help="a checkout whose src/ to run the same cases on")
    p.add_argument("--json", action="store_true", help=argparse.SUPPRESS)
    args = p.parse_args()
    batches = [int(b) for b in args.batch.split(",")]
    rows = [("this", *row) for row in measure(batches, args.ds)]
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
        f"{'designs/s':>11}{'designs/cpu s':>15}{'cpu s/design':>14}"
    )
    for code, name, n, wall, cpu in rows:
        print(
            f"{code:<11}{name:<28}{n:>8}{wall:>10.2f}{cpu:>10.2f}{n / wall:>11.3f}"
            f"{n / cpu:>15.3f}{cpu / n:>14.4f}"
        )


if __name__ == "__main__":
    main()
