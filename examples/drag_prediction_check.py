"""Prediction check: the reduced model fed with drag-test parameters against the FE crawler.

For each inclination: one drag test of the paper's bristle at that inclination (back and
forth over the grooves), which gives k, F_p and F_n; then, for each peak shortening s~,
the FE crawler (two cycles of the sin^2 stroke, period 20 s) and the reduced model's exact
solver with the drag-test bristles on the same gait. Prints the table of net advance and
work with the errors, and writes it as CSV with ``--out``::

    python examples/drag_prediction_check.py                 # alpha 30/45/60, s~ 4/8/12/20
    python examples/drag_prediction_check.py --alphas 45 --strokes 20 --cycles 5

About 20 FE runs in all: half an hour on a 2-core machine.
"""

from __future__ import annotations

import argparse
import csv
import time

from bristlecrawler.crawler import Actuation, CrawlerSpec, run
from bristlecrawler.crawler.drag import DragTest, drag_test
from bristlecrawler.crawler.prediction import Prediction, compare
from bristlecrawler.fe import enable_compilation_cache

DRAG = DragTest(direction="cycle", distance=10.0, speed=2.0)


def design(alpha_deg: float, s_max: float, cycles: int) -> CrawlerSpec:
    """The paper's crawler with both bristles at ``alpha_deg`` and the stroke ``s_max``."""
    spec = CrawlerSpec.paper(actuation=Actuation(s_max=s_max, cycles=cycles))
    return spec.replace_bristles(alpha_deg=alpha_deg)


def check(alphas, strokes, cycles: int, drag: DragTest = DRAG):
    """Yield (drag summary, :class:`Prediction`) for every inclination and stroke."""
    for alpha in alphas:
        d = drag_test(design(alpha, strokes[0], cycles), drag)
        summary = d.summary()
        for s in strokes:
            spec = design(alpha, s, cycles)
            yield summary, compare(spec, d, run(spec))


def _print_row(summary: dict, p: Prediction) -> None:
    r = p.row()
    fe = " ".join(f"{v:.2f}" for v in p.fe_per_cycle)
    red = " ".join(f"{v:.2f}" for v in p.reduced_per_cycle)
    print(
        f"| {r['alpha_deg']:.0f} | {r['s_max_mm']:.0f} | {summary['k_N_per_mm']:.3f} | "
        f"{summary['fp_N']:.3f} | {summary['fn_N']:.3f} | {fe} | {red} | "
        f"{r['advance_error_mm']:+.2f} | {r['fe_work_mJ']:.2f} | {r['reduced_work_mJ']:.2f} | "
        f"{100 * r['work_error_rel']:+.1f} % |",
        flush=True,
    )


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--alphas", type=float, nargs="+", default=[30.0, 45.0, 60.0])
    ap.add_argument("--strokes", type=float, nargs="+", default=[4.0, 8.0, 12.0, 20.0])
    ap.add_argument("--cycles", type=int, default=2)
    ap.add_argument("--out", help="CSV file for the table")
    args = ap.parse_args(argv)
    enable_compilation_cache()
    print(
        "| alpha (deg) | s~ (mm) | k (N/mm) | F_p (N) | F_n (N) | FE advance per cycle (mm) "
        "| reduced (mm) | reduced - FE (mm) | FE work (mJ) | reduced work (mJ) | work error |"
    )
    print("|---" * 11 + "|")
    rows, t0 = [], time.perf_counter()
    for summary, p in check(args.alphas, args.strokes, args.cycles):
        _print_row(summary, p)
        keep = ("k_N_per_mm", "k_unload_N_per_mm", "fp_N", "fn_N", "fp_scatter_N", "fn_scatter_N")
        cycles = {f"fe_cycle_{i + 1}_mm": v for i, v in enumerate(p.fe_per_cycle)}
        rows.append(p.row() | {k: summary[k] for k in keep} | cycles)
    print(f"\n{len(rows)} designs in {time.perf_counter() - t0:.0f} s")
    if args.out:
        with open(args.out, "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=list(rows[0]))
            w.writeheader()
            w.writerows(rows)


if __name__ == "__main__":
    main()
