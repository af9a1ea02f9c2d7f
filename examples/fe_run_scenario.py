"""Run a finite-element crawler scenario from Python and read its gait.

The inclined bristles (alpha = 45 deg, the ``paper`` scenario) make the crawler advance
along the grain; the same crawler with vertical bristles (the ``paper-vertical``
scenario) on a texture placed mirror-symmetrically under it has no preferred direction:
round-off decides whether a bowing bristle lets a tip slip into the next groove, so it
stays or shifts by one pitch (2 mm), either way.

To keep this example quick (seconds after a one-off compilation), both runs are one
8 mm stroke in 4 s of the paper's crawler, its mesh and contact unchanged. A coarser
model does not crawl: with 4 elements per bristle and contact at the tips' axis points
only, the tips cannot climb out of their grooves (a point against a vertical wall), and
the stroke only flexes the bristles (docs/findings.md). Drop ``QUICK`` for the paper's
five 20 mm cycles (about a minute, after compilation)::

    python examples/fe_run_scenario.py
"""

from __future__ import annotations

from bristlecrawler.crawler import run
from bristlecrawler.fe import enable_compilation_cache
from bristlecrawler.scenario import load_spec

#: One short stroke: scenario overrides as on the command line (``--set``).
QUICK = [
    "actuation.s_max=8.0",  # mm
    "actuation.period=4.0",  # s
    "actuation.cycles=1",
]
#: Grooves [0.5, 1.5] + 2k mm: lands centred under both vertical tips and under the
#: body's middle, so the vertical crawler's problem is mirror symmetric.
MIRROR = ["substrate.phase=0.5"]

enable_compilation_cache()  # compiled programs are kept on disk for the next run

# A scenario (shipped name or TOML file) with --set style overrides, as the plain
# CrawlerSpec the FE crawler runs; then built and run with the paper's stages.
inclined = load_spec("paper", QUICK)
vertical = load_spec("paper-vertical", QUICK + MIRROR)

runs = {spec.bristles[0].alpha_deg: run(spec) for spec in (inclined, vertical)}
stroke_mm = inclined.actuation.s_max
advance_inclined_mm = float(runs[45.0].net_advance)
advance_vertical_mm = float(runs[0.0].net_advance)
work_inclined_mJ = float(runs[45.0].connector_work[-1])


def main() -> None:
    for alpha, h in runs.items():
        print(
            f"alpha = {alpha:4.1f} deg: net advance {h.net_advance:+.4f} mm, "
            f"connector work {h.connector_work[-1]:.3f} mJ, {h.t.size - 1} steps"
        )


if __name__ == "__main__":
    main()
