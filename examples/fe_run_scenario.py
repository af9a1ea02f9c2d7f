"""Run a finite-element crawler scenario from Python and read its gait.

The inclined bristles (alpha = 45 deg, the ``paper`` scenario) make the crawler advance
along the grain; the same crawler with vertical bristles (alpha = 0) on a texture placed
mirror-symmetrically under it cannot choose a direction and stays where it is.

To keep this example quick (seconds after a one-off compilation) both runs are a short,
coarse version of the paper's: ``QUICK`` below takes 4 elements per bristle, contact at
the tips' axis points and a 2 mm stroke in 1 s. Drop ``QUICK`` for the paper's five
20 mm cycles (about half a minute on a laptop, after compilation)::

    python examples/fe_run_scenario.py
"""

from __future__ import annotations

from bristlecrawler.crawler import run
from bristlecrawler.fe import enable_compilation_cache
from bristlecrawler.scenario import load_spec

#: A short, coarse run: scenario overrides as on the command line (``--set``).
QUICK = [
    "bristle.elements=4",
    "contact.nodes='tip'",
    "contact.surface=false",
    "contact.corners=false",
    "substrate.phase=0.5",  # grooves at [0.5, 1.5] + 2k mm: lands under both tips
    "actuation.s_max=2.0",  # mm
    "actuation.period=1.0",  # s
    "actuation.cycles=1",
    "actuation.settle_time=0.2",  # s of gravity step
]

enable_compilation_cache()  # compiled programs are kept on disk for the next run

# A scenario (shipped name or TOML file) with --set style overrides, as the plain
# CrawlerSpec the FE crawler runs; then built and run with the paper's stages.
inclined = load_spec("paper", QUICK)
vertical = inclined.replace_bristles(alpha_deg=0.0)

runs = {spec.bristles[0].alpha_deg: run(spec) for spec in (inclined, vertical)}
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
