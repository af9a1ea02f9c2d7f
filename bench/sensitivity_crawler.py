"""Sensitivity of the FE crawler to the inputs the paper does not give.

The groove pitch (default 2 mm) and the length of the rigid links from the body down to
the bristle clamps (default 10 mm) are not in the paper. This study runs the scenario
(default ``paper``) at its own values and then varies one input at a time, printing one
row per run: net advance, connector work, their changes against the base run, the mean
|F_c|, the first frequency after the gravity step and the advance of each cycle. Nothing
is asserted: each row is a full simulation (about a minute per cycle on the 2-core
machine, plus a compilation for every substrate that changes the corner window).

    python bench/sensitivity_crawler.py [--scenario paper] [--cycles 2]
        [--vary substrate.pitch=1.5,2.5,3,4] [--vary body.link_length=5,20]
        [--set section.key=value ...]

Without ``--vary`` the two defaults above are run. The tips start where the scenario puts
them (a groove's left wall at ``substrate.phase``), so a new pitch also moves the tips'
starting place relative to the grooves, as a new texture under the same crawler would.
"""

from __future__ import annotations

import argparse

from _crawler_rows import run_rows

DEFAULT_VARY = ["substrate.pitch=1.5,2.5,3,4", "body.link_length=5,20"]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scenario", default="paper")
    ap.add_argument("--cycles", type=int, default=2)
    ap.add_argument("--vary", action="append", default=[])
    ap.add_argument("--set", dest="sets", action="append", default=[])
    a = ap.parse_args()

    from bristlecrawler.fe import enable_compilation_cache
    from bristlecrawler.scenario.load import apply_overrides, load_scenario

    enable_compilation_cache()
    base = apply_overrides(load_scenario(a.scenario), [*a.sets, f"actuation.cycles={a.cycles}"])
    variants = [("base", [])]
    for spec in a.vary or DEFAULT_VARY:
        key, _, values = spec.partition("=")
        if not values:
            raise SystemExit(f"--vary needs section.key=v1,v2,...: got {spec!r}")
        for v in values.split(","):
            sets = [f"{key}={v}"]
            apply_overrides(base, sets)  # a bad value stops here, before any run
            variants.append((f"{key.split('.')[-1]} {v}", sets))
    print(
        f"scenario {base.name}, {a.cycles} cycle(s): pitch {base.substrate.pitch:g} mm, "
        f"link length {base.body.link_length:g} mm, {base.bristle.elements} elements per "
        "bristle"
    )
    run_rows(base, variants, extra_columns=True)


if __name__ == "__main__":
    main()
