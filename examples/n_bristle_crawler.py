"""FE crawlers with 2, 3 and 4 bristles against the reduced model on the same gait.

The body keeps the paper's 100 mm between its first and last bristle and its 55 g; the
bristles are the paper's, spread evenly, and every segment between two of them shortens by
s(t) = 20 sin^2(pi t / 20) mm at once (the breathing gait). The reduced model runs the
same gait with the paper's calibrated bristles (F_p = 0.456 N, k = 0.48 N/mm, F_n = 3 F_p)
in its exact solver.

Run ``python examples/n_bristle_crawler.py [--cycles 2]`` (a few minutes: three FE runs);
the test suite imports :func:`compare` and runs it on a short, coarse crawler.
"""

from __future__ import annotations

import argparse
import dataclasses
from dataclasses import dataclass

import numpy as np

import bristlecrawler as bc
from bristlecrawler.crawler import DEFAULT_STAGES, Actuation, CrawlerSpec, run


@dataclass(frozen=True)
class Row:
    """One design: FE and reduced advance per cycle (mm), FE work (mJ), FE balance error,
    and the FE run's :class:`CrawlerHistory`."""

    bristles: int
    fe_per_cycle: np.ndarray
    reduced_per_cycle: np.ndarray
    fe_work: float
    balance_error: float
    history: object


def reduced_per_cycle(spec: CrawlerSpec) -> np.ndarray:
    """Advance per cycle (mm) of the reduced model on ``spec``'s body and gait."""
    a = spec.actuation
    crawler = bc.ReducedCrawler.uniform(len(spec.bristles), length=spec.body.length)
    result = bc.simulate(crawler, bc.Sin2Stroke(a.s_max, a.period), cycles=a.cycles)
    return np.asarray(result.per_cycle()[0])


def compare(n_bristles: int, spec: CrawlerSpec, stages=DEFAULT_STAGES) -> Row:
    """Run ``spec`` with ``n_bristles`` spread over its body, FE (``stages``) and reduced."""
    spec = spec.with_bristles(n_bristles)
    h = run(spec, stages)
    return Row(
        bristles=n_bristles,
        fe_per_cycle=h.advance_per_cycle(),
        reduced_per_cycle=reduced_per_cycle(spec),
        fe_work=float(h.connector_work[-1]),
        balance_error=h.energy_balance_rel_error(),
        history=h,
    )


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cycles", type=int, default=2)
    ap.add_argument("--bristles", type=int, nargs="+", default=[2, 3, 4])
    args = ap.parse_args(argv)
    spec = CrawlerSpec.paper(actuation=Actuation(cycles=args.cycles))
    spec = dataclasses.replace(spec, name="n-bristle")
    print("| bristles | FE advance per cycle (mm) | reduced (mm) | FE work (mJ) | balance |")
    print("|---|---|---|---|---|")
    for n in args.bristles:
        r = compare(n, spec)
        fe = ", ".join(f"{a:.2f}" for a in r.fe_per_cycle)
        red = ", ".join(f"{a:.2f}" for a in r.reduced_per_cycle)
        print(f"| {n} | {fe} | {red} | {r.fe_work:.2f} | {r.balance_error:.1e} |", flush=True)


if __name__ == "__main__":
    main()
