"""Benchmark of the reduced model on a texture: two-bristle designs in a batch, and the
event-driven solver for 2-4 bristles.

Run: ``python bench/bench_texture.py [--law summary.json]``. Prints a table; nothing is
asserted. The law is a drag test's (``summary.json`` of ``bristlecrawler drag``, key
``texture``) or, without one, a 16-cell law with the paper's groove shape. Target: at
least 1e4 two-bristle design evaluations (two cycles, strokes 8-20 mm) per second. Both
wall and process (CPU) time are given: on a shared machine the wall time is the load's.
"""

from __future__ import annotations

import argparse
import json
import os
import time

import numpy as np

from bristlecrawler.reduced import Sin2Stroke, simulate
from bristlecrawler.reduced.textured import TexturedCrawler
from bristlecrawler.reduced.textured_pair import PairBatch, pair_cycles
from bristlecrawler.results.texture import TextureLaw


def groove_like_law() -> TextureLaw:
    """A 2 mm pitch law shaped like the paper's bristle on its grooves (N, mm)."""
    fp = np.r_[np.linspace(0.33, 0.24, 9), np.full(7, 0.18)]
    fn = np.r_[0.23, 0.18, 0.14, np.full(6, 0.03), 0.29, 0.03, np.full(5, 0.48)]
    return TextureLaw(2.0, fp, fn, 1.38, tip_offset_mm=-3.66)


def timed(fn):
    t0, c0 = time.perf_counter(), time.process_time()
    out = fn()
    return out, time.perf_counter() - t0, time.process_time() - c0


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__)
    p.add_argument("--law", help="a drag test's summary.json with a texture law")
    args = p.parse_args()
    law = (
        TextureLaw.from_dict(json.load(open(args.law))["texture"])
        if args.law
        else groove_like_law()
    )
    print(f"law: {law.n_cells} cells over {law.pitch_mm:g} mm, load {os.getloadavg()[0]:.1f}")
    print(f"{'case':52s} {'wall s':>8s} {'cpu s':>8s} {'designs/s (wall, cpu)':>24s}")
    for B in (1_000, 10_000, 100_000):
        batch = PairBatch.of([law] * B, 100.0, np.linspace(8.0, 20.0, B))
        _, wall, cpu = timed(lambda batch=batch: pair_cycles(batch, cycles=2))
        name = f"two bristles, batch of {B}, 2 cycles"
        print(f"{name:52s} {wall:8.3f} {cpu:8.3f} {B / wall:11.0f} {B / cpu:11.0f}")
    for n in (2, 3, 4):
        crawler = TexturedCrawler.uniform(law, n)
        res, wall, cpu = timed(
            lambda c=crawler: simulate(c, Sin2Stroke(20.0, 20.0), 2, samples_per_cycle=400)
        )
        name = f"event solver, {n} bristles, 2 cycles x 400 samples ({len(res.events)} ev)"
        print(f"{name:52s} {wall:8.3f} {cpu:8.3f} {1 / wall:11.1f} {1 / cpu:11.1f}")


if __name__ == "__main__":
    main()
