"""Prediction of the FE crawler on grooves: the texture model against the paper's model.

For each design (a set of scenario overrides on ``paper``): the drag test of its bristle
on its substrate (cached, as ``bristlecrawler predict`` does), the reduced crawler on the
texture law it gives, the paper's reduced model with its k, F_p and F_n, and the FE
crawler's steady cycle (the last of two) and work. A prediction hits when its steady-cycle
advance is within half a pitch of the FE's. ::

    python examples/texture_prediction.py                 # the designs with FE results below
    python examples/texture_prediction.py --grid --fe --out runs/texture-grid.jsonl

``FE_MEASURED`` holds FE results of the findings (docs/findings.md: the pitch study and
the bristle-count study, two cycles of s~ = 20 mm at 45 degrees), so that the table needs
no FE run; ``--fe`` runs the FE crawler for every design instead (minutes each).
``--out FILE.jsonl`` appends each design's row (or its failure) as it finishes, and a
second run with the same file skips the designs already in it.

Each row carries the FE run's quality warnings (``warnings``: those ``bristlecrawler
simulate`` prints, such as a bristle strain outside the beam model; null for the stored
results, whose warnings were not kept), and the table shows them in its "why" column.
"""

from __future__ import annotations

import argparse
import itertools
import json
import time
from pathlib import Path

import numpy as np

from bristlecrawler.scenario.convert import to_spec
from bristlecrawler.scenario.load import apply_overrides, load_scenario

#: FE crawler, two cycles: (advance per cycle mm, work over both cycles mJ), from
#: docs/findings.md (``bristlecrawler simulate paper --cycles 2 --set ...`` and
#: ``python examples/n_bristle_crawler.py --cycles 2 --bristles 2 3 4``).
FE_MEASURED = {
    ("substrate.pitch=1.5",): ((18.53, 18.00), 19.26),
    (): ((17.60, 16.00), 17.83),
    ("substrate.pitch=2.5",): ((16.12, 15.00), 16.68),
    ("substrate.pitch=3.0",): ((18.45, 18.00), 16.59),
    ("substrate.pitch=4.0",): ((15.60, 12.00), 15.57),
    ("bristle.count=3",): ((28.01, 28.00), 35.03),
    ("bristle.count=4",): ((35.30, 34.01), 49.90),
}


def grid() -> list[tuple[str, ...]]:
    """24 designs: inclination 30/45/60 degrees x pitch 1.5/2/3/4 mm, with 2, 3 or 4
    bristles and strokes from 8 to 20 mm in turn."""
    out = []
    for j, (alpha, pitch) in enumerate(itertools.product((30, 45, 60), (1.5, 2.0, 3.0, 4.0))):
        for m in range(2):
            i = 2 * j + m
            out.append(
                (
                    f"bristle.alpha_deg={alpha}",
                    f"substrate.pitch={pitch}",
                    f"bristle.count={2 + i % 3}",
                    f"actuation.s_max={8 + (5 * i) % 13}",
                )
            )
    return out


def scenario(overrides):
    return apply_overrides(load_scenario("paper"), [*overrides, "actuation.cycles=2"])


def fe_run(sc) -> tuple[tuple[float, ...], float, list[str]]:
    """The FE crawler's advance per cycle (mm), work (mJ) and quality warnings, the
    warnings being those of ``bristlecrawler simulate`` (its summary's)."""
    from bristlecrawler.crawler import run
    from bristlecrawler.jobs.simulate import summarize

    h = run(to_spec(sc))
    adv = tuple(float(a) for a in h.advance_per_cycle())
    return adv, float(h.connector_work[-1]), list(summarize(h, sc)["warnings"])


def design_name(overrides) -> str:
    return " ".join(overrides) or "paper"


def is_cached(overrides) -> bool:
    """Whether the design's drag test is in the drag cache."""
    from bristlecrawler.jobs.predict import cache_folder, cache_key, prediction_drag_test

    sc = scenario(overrides)
    key = cache_key(sc, prediction_drag_test(to_spec(sc)))
    return (cache_folder() / f"{key}.json").is_file()


def evaluate(overrides, fe=None) -> dict:
    """One design's row: FE (run, or given as advance per cycle and work, with or
    without its warnings), texture and paper models."""
    from bristlecrawler.jobs.predict import cached_drag, predict_models, prediction_drag_test

    sc = scenario(overrides)
    spec = to_spec(sc)
    summary, _ = cached_drag(sc, prediction_drag_test(spec))
    models = predict_models(spec, summary, cycles=2)
    fe = fe if fe is not None else fe_run(sc)
    warnings = list(fe[2]) if len(fe) > 2 else None
    return row_of(design_name(overrides), summary.texture, models, fe[0], fe[1], warnings)


def row_of(name, law, models, fe_adv, fe_work, warnings=None) -> dict:
    """A design's row from its texture ``law``, the reduced ``models``' metrics and the
    FE crawler's advance per cycle (mm), work (mJ) and warnings (None: not known)."""
    pitch = law.pitch_mm
    row = {
        "design": name,
        "pitch_mm": pitch,
        "fe_advance_per_cycle_mm": list(fe_adv),
        "fe_steady_mm": fe_adv[-1],
        "k_N_per_mm": law.k_N_per_mm,
        "warnings": warnings,
    }
    for name, m in models.items():
        steady = m.advance_per_cycle[-1]
        row[f"{name}_steady_mm"] = steady
        row[f"{name}_advance_per_cycle_mm"] = list(m.advance_per_cycle)
        row[f"{name}_work_mJ"] = m.work
        row[f"{name}_hit"] = abs(steady - fe_adv[-1]) <= 0.5 * pitch
        row[f"{name}_work_error"] = m.work / fe_work - 1.0
    row["fe_work_mJ"] = fe_work
    return row


def why(row) -> str:
    """The row's FE warnings in one line (empty without any, or for a row of a file
    written before rows carried them)."""
    return "; ".join(row.get("warnings") or ())


def markdown(rows) -> str:
    """The rows as the findings' table."""
    head = (
        "| design | pitch (mm) | FE steady cycle (mm) | texture model (mm) | paper's model "
        "(mm) | FE work (mJ) | texture work | paper work | why |\n"
        "|---|---|---|---|---|---|---|---|---|"
    )
    lines = [head]
    for r in rows:
        lines.append(
            f"| {r['design']} | {r['pitch_mm']:g} | {r['fe_steady_mm']:.2f} | "
            f"{r['texture_steady_mm']:.2f}{'' if r['texture_hit'] else ' (miss)'} | "
            f"{r['paper_steady_mm']:.2f}{'' if r['paper_hit'] else ' (miss)'} | "
            f"{r['fe_work_mJ']:.2f} | {r['texture_work_error']:+.1%} | "
            f"{r['paper_work_error']:+.1%} | {why(r)} |"
        )
    return "\n".join(lines)


def main(argv=None) -> list[dict]:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--grid", action="store_true", help="the 24-design grid (needs --fe)")
    p.add_argument("--fe", action="store_true", help="run the FE crawler for every design")
    p.add_argument(
        "--cached-only", action="store_true", help="skip designs whose drag test is not cached"
    )
    p.add_argument("--markdown", action="store_true", help="print the table as Markdown")
    p.add_argument("--out", type=Path, help="JSON lines file: one row per design, resumable")
    p.add_argument(
        "--table-only", action="store_true", help="the table of the designs in --out, run none"
    )
    p.add_argument(
        "--only",
        type=lambda s: [int(x) for x in s.split(",")],
        help="run only these designs, by their place in the list from 0 (e.g. 0,5,7): "
        "to share the grid out between processes, each with its own --out",
    )
    args = p.parse_args(argv)
    if args.grid and not args.fe:
        p.error("--grid needs --fe (the grid's designs have no stored FE results)")
    designs = grid() if args.grid else list(FE_MEASURED)
    if args.only is not None:
        bad = [i for i in args.only if not 0 <= i < len(designs)]
        if bad:
            p.error(f"--only: no design {bad[0]} (there are {len(designs)}, from 0)")
        designs = [designs[i] for i in args.only]
    done = {}
    if args.out is not None and args.out.is_file():
        for line in args.out.read_text().splitlines():
            if line.strip():
                entry = json.loads(line)
                done[entry["design"]] = entry
    rows, failed = [], []
    for d in designs:
        name = design_name(d)
        if name in done:
            (failed if "error" in done[name] else rows).append(done[name])
            continue
        if args.table_only:
            continue
        if args.cached_only and not is_cached(d):
            print(f"{name}: no cached drag test, skipped")
            continue
        t0 = time.perf_counter()
        try:
            entry = evaluate(d, None if args.fe else FE_MEASURED[d])
            rows.append(entry)
        except Exception as exc:  # a design that fails is reported, the others go on
            entry = {"design": name, "error": f"{type(exc).__name__}: {exc}"}
            failed.append(entry)
            print(f"{name}: {entry['error']}")
        entry["wall_s"] = time.perf_counter() - t0
        if args.out is not None:
            args.out.parent.mkdir(parents=True, exist_ok=True)
            with args.out.open("a") as f:
                f.write(json.dumps(entry) + "\n")
    print(
        f"{'design':40s} {'FE':>6s} {'texture':>8s} {'paper':>6s}  "
        f"{'work err (tex, paper)':21s}  why"
    )
    for r in rows:
        errors = f"{r['texture_work_error']:+.1%} {r['paper_work_error']:+.1%}"
        print(
            f"{r['design']:40s} {r['fe_steady_mm']:6.2f} {r['texture_steady_mm']:8.2f} "
            f"{r['paper_steady_mm']:6.2f}  {errors:21s}  {why(r)}".rstrip()
        )
    if args.markdown:
        print(markdown(rows))
    for entry in failed:
        print(f"failed: {entry['design']}: {entry['error']}")
    for name in ("texture", "paper"):
        hits = sum(r[f"{name}_hit"] for r in rows)
        err = np.abs([r[f"{name}_work_error"] for r in rows])
        print(
            f"{name}: {hits}/{len(rows)} within half a pitch; work error median "
            f"{np.median(err):.1%}, max {err.max():.1%}"
            if rows
            else f"{name}: no designs"
        )
    return rows


if __name__ == "__main__":
    main()
