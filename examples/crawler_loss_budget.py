"""Where the FE crawler's stroke goes: the advance, the holding tips' backslip, elastic lag.

The reduced model loses 4 F_p / k of every steady cycle to the bristles' elasticity: each
reversal must load the holding bristle from +F_p to -F_p before it holds. On the grooved
substrate the FE crawler loses more (16 of 20 mm advance, not 19.4 as the drag test's k
and F_p would give). This script splits each cycle of the paper's two-bristle crawler
into what the tips' recorded positions show:

* backslip: how far each holding tip slides backwards (against the direction of travel),
  summed over the cycle; on the grooves it slides until a groove wall catches it;
* elastic lag: the rest, the change of the bristles' deflection (clamp minus tip);

and fits the bristles' in-situ stiffness: the connector force against the front bristle's
deflection while its tip sticks, to set beside the drag test's k. ::

    python examples/crawler_loss_budget.py [--cycles 3]
"""

from __future__ import annotations

import argparse
import itertools

import numpy as np

from bristlecrawler.crawler import Actuation, CrawlerSpec, run
from bristlecrawler.fe import enable_compilation_cache
from bristlecrawler.states import ContactState


def budget(h) -> list[dict]:
    """Per cycle: stroke (mm), advance of the front end (mm), backward travel of each tip
    (mm), and the rest of the stroke (elastic lag, mm)."""
    b = h.cycle_bounds()
    out = []
    for i0, i1 in itertools.pairwise(b):
        tips = h.tip_position[i0 : i1 + 1, :, 0]
        back = -np.minimum(np.diff(tips, axis=0), 0.0).sum(axis=0)
        stroke = float(h.s[i0 : i1 + 1].max())
        advance = float(h.delta[i1] - h.delta[i0])
        out.append(
            {
                "stroke_mm": stroke,
                "advance_mm": advance,
                "rear_backslip_mm": float(back[0]),
                "front_backslip_mm": float(back[-1]),
                "elastic_lag_mm": stroke - advance - float(back.sum()),
            }
        )
    return out


def in_situ_stiffness(h) -> float:
    """N/mm: least-squares slope of the connector force against the front bristle's
    deflection (front clamp x minus its tip x) over the samples where its tip sticks."""
    stick = h.tip_state[:, -1] == ContactState.STICK
    deflection = h.right[:, 0] - h.tip_position[:, -1, 0]
    force = -h.connector_force  # the connector pulls the front end back on contraction
    slopes = []
    edges = np.flatnonzero(np.diff(np.concatenate([[0], stick.astype(int), [0]])))
    for a, b in zip(edges[::2], edges[1::2], strict=True):
        if b - a >= 20 and np.ptp(deflection[a:b]) > 0.05:
            slopes.append(abs(np.polyfit(deflection[a:b], force[a:b], 1)[0]))
    return float(np.median(slopes)) if slopes else float("nan")


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cycles", type=int, default=3)
    args = ap.parse_args(argv)
    enable_compilation_cache()
    h = run(CrawlerSpec.paper(actuation=Actuation(cycles=args.cycles)))
    print("| cycle | stroke (mm) | advance (mm) | rear backslip (mm) | front backslip (mm) "
          "| elastic lag (mm) |")  # fmt: skip
    print("|---" * 6 + "|")
    for i, r in enumerate(budget(h)):
        print(
            f"| {i + 1} | {r['stroke_mm']:.2f} | {r['advance_mm']:.2f} | "
            f"{r['rear_backslip_mm']:.2f} | {r['front_backslip_mm']:.2f} | "
            f"{r['elastic_lag_mm']:.2f} |"
        )
    print(f"\nin-situ stiffness of the front bristle: {in_situ_stiffness(h):.3f} N/mm")


if __name__ == "__main__":
    main()
