"""The table "paper versus bristlecrawler" of a full ``reproduce`` run, as the README shows it.

Runs every part of ``bristlecrawler reproduce`` with the full settings except the design
study (no row of the table reads it), writes the run folder, and copies its ``table.json``
to ``docs/results/table.json``, the source of the README's table (a test checks that the
README shows it). ``--readme`` prints the README's table from that file.

    python bench/reference_table.py --out runs/reference
    python bench/reference_table.py --readme
"""

from __future__ import annotations

import argparse
import json
import shutil
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
TABLE = ROOT / "docs" / "results" / "table.json"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=None, help="run folder")
    parser.add_argument("--readme", action="store_true", help="print the README's table")
    args = parser.parse_args()
    if args.readme:
        from bristlecrawler.jobs.reproduce.table import readme_table

        print(readme_table(json.loads(TABLE.read_text())), end="")
        return
    from bristlecrawler.cli.app import quiet_xla

    quiet_xla()
    from bristlecrawler.jobs.reproduce import ReproduceOptions, run_reproduce
    from bristlecrawler.jobs.reproduce.run import PARTS

    parts = tuple(p for p in PARTS if p.name != "study")
    t0 = time.perf_counter()
    opts = ReproduceOptions(out=args.out, parts=parts, command="bench/reference_table.py")
    run = run_reproduce(opts)
    wall = time.perf_counter() - t0
    TABLE.parent.mkdir(parents=True, exist_ok=True)
    shutil.copyfile(run.out_dir / "table.json", TABLE)
    for name, r in run.results.items():
        print(f"{name:12s} {r.wall_s:8.0f} s  {'ok' if r.ok else 'FAILED: ' + r.error}")
    print(f"{'total':12s} {wall:8.0f} s; table: {TABLE}")


if __name__ == "__main__":
    main()
