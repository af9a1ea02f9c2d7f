"""The bristled model against every FE crawler design with a result in the findings.

Each design is a set of scenario overrides on ``paper`` (two cycles); the bristled model
plays it with no FE in the loop (:mod:`bristlecrawler.reduced.bristled`, through the same
adapter ``bristlecrawler predict`` uses), and its steady cycle (the second) and work are
set against the FE crawler's. ::

    python examples/bristled_prediction.py              # the table, as markdown
    python examples/bristled_prediction.py --only 2     # the two-bristle designs only
    python examples/bristled_prediction.py --only 2 --ds 0.05   # with finer steps of s

``FE_RESULTS`` holds the FE numbers of docs/findings.md (the pitch study, the bristle-count
study, the three-bristle design at 30 degrees, and the grid designs that finished).
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from bristlecrawler.crawler.bristled import bristled_design
from bristlecrawler.reduced.bristled import RunOptions, run
from bristlecrawler.scenario.convert import to_spec
from bristlecrawler.scenario.load import apply_overrides, load_scenario

#: Overrides on ``paper`` -> (FE advance per cycle mm, FE work over both cycles mJ, note).
FE_RESULTS = {
    ("substrate.pitch=1.5",): ((18.53, 18.00), 19.26, ""),
    (): ((17.60, 16.00), 17.83, ""),
    ("substrate.pitch=2.5",): ((16.12, 15.00), 16.68, ""),
    ("substrate.pitch=3.0",): ((18.45, 18.00), 16.59, ""),
    ("substrate.pitch=4.0",): ((15.60, 12.00), 15.57, ""),
    ("bristle.count=3",): ((28.01, 28.00), 35.03, ""),
    ("bristle.count=4",): ((35.30, 34.01), 49.90, ""),
    ("bristle.count=3", "bristle.alpha_deg=30", "substrate.pitch=3.0"): (
        (26.14, 21.08),
        30.64,
        "",
    ),
    ("bristle.alpha_deg=30", "substrate.pitch=1.5", "actuation.s_max=8"): (
        (6.68, 6.00),
        7.12,
        "",
    ),
    (
        "bristle.alpha_deg=30",
        "substrate.pitch=1.5",
        "bristle.count=3",
        "actuation.s_max=13",
    ): ((18.69, 16.51), 27.53, ""),
    ("bristle.alpha_deg=30", "substrate.pitch=2.0", "actuation.s_max=10"): (
        (6.46, 6.01),
        8.76,
        "",
    ),
    ("substrate.pitch=1.5", "actuation.s_max=14"): (
        (-0.10, 0.01),
        16.15,
        "FE bristle folds at the tip (bending strain 1.17): not to be trusted",
    ),
    ("substrate.pitch=3.0", "actuation.s_max=16"): ((12.51, 12.00), 12.85, ""),
    ("substrate.pitch=4.0", "actuation.s_max=18"): ((15.60, 12.00), 14.24, ""),
}


def spec_of(overrides):
    sc = apply_overrides(load_scenario("paper"), [*overrides, "actuation.cycles=2"])
    return to_spec(sc)


def rows(only: int | None = None, options: RunOptions | None = None):
    """One row per design: the FE's and the bristled model's advance and work."""
    options = options or RunOptions()
    items = [(o, fe) for o, fe in FE_RESULTS.items()]
    specs = [spec_of(o) for o, _ in items]
    out = []
    for count in sorted({len(s.bristles) for s in specs}):
        if only is not None and count != only:
            continue
        pick = [i for i, s in enumerate(specs) if len(s.bristles) == count]
        start = time.perf_counter()
        r = run([bristled_design(specs[i]) for i in pick], cycles=2, options=options)
        seconds = (time.perf_counter() - start) / len(pick)
        for k, i in enumerate(pick):
            (fe_adv, fe_work, note), spec = items[i][1], specs[i]
            pitch = float(np.asarray(spec.substrate.pitch))
            model_adv = r.advance_per_cycle[k]
            miss = abs(model_adv[-1] - fe_adv[-1])
            out.append(
                {
                    "design": " ".join(items[i][0]) or "paper",
                    "bristles": count,
                    "pitch_mm": pitch,
                    "fe_per_cycle_mm": fe_adv,
                    "model_per_cycle_mm": tuple(float(a) for a in model_adv),
                    "within_pitch": bool(miss <= pitch),
                    "within_half_pitch": bool(miss <= 0.5 * pitch),
                    "fe_work_mJ": fe_work,
                    "model_work_mJ": float(r.work[k]),
                    "work_error": float(r.work[k] / fe_work - 1.0),
                    "ok": bool(r.ok[k]),
                    "seconds": seconds,
                    "note": note,
                }
            )
    return out


def markdown(table) -> str:
    head = (
        "| design | pitch (mm) | FE per cycle (mm) | bristled model (mm) | steady-cycle miss"
        " | FE work (mJ) | model work |\n|---|---|---|---|---|---|---|"
    )
    lines = [head]
    for r in table:
        miss = abs(r["model_per_cycle_mm"][-1] - r["fe_per_cycle_mm"][-1])
        tag = "" if r["within_half_pitch"] else (" (> half)" if r["within_pitch"] else " (> pitch)")
        flag = "" if r["ok"] else " (did not settle)"
        lines.append(
            f"| {r['design']} | {r['pitch_mm']:g} | "
            f"{', '.join(f'{a:.2f}' for a in r['fe_per_cycle_mm'])} | "
            f"{', '.join(f'{a:.2f}' for a in r['model_per_cycle_mm'])}{flag} | "
            f"{miss:.2f} mm{tag} | {r['fe_work_mJ']:.2f} | {100 * r['work_error']:+.1f} % |"
        )
    return "\n".join(lines)


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--only", type=int, help="only the designs with this many bristles")
    parser.add_argument("--ds", type=float, default=RunOptions.ds, help="stroke step, mm")
    args = parser.parse_args(argv)
    table = rows(args.only, RunOptions(ds=args.ds))
    print(markdown(table))
    n = len(table)
    one = sum(r["within_pitch"] for r in table)
    half = sum(r["within_half_pitch"] for r in table)
    work = sum(abs(r["work_error"]) <= 0.15 for r in table)
    print(
        f"\nwithin one pitch {one}/{n}, within half a pitch {half}/{n}, work within 15 % {work}/{n}"
    )


if __name__ == "__main__":
    main()
