"""Change the texture: the same crawler on grooves of three pitches.

The groove pitch is not given in the paper (the shipped scenarios assume 2 mm), and it
matters: the holding tip rests in a groove, so the advance comes in whole pitches (the
docs' findings page). Any ``[substrate]`` key can be changed the same way, from Python
as here or with ``--set substrate.pitch=3.0`` on the command line, or in a scenario file
that starts from ``base = "paper"``.

Short, coarse runs (see ``fe_run_scenario.py``); drop ``QUICK`` for the paper's run::

    python examples/fe_texture_pitch.py
"""

from __future__ import annotations

import dataclasses

from bristlecrawler.contact import Grooves
from bristlecrawler.crawler import run
from bristlecrawler.fe import enable_compilation_cache
from bristlecrawler.scenario import load_spec

QUICK = [
    "bristle.elements=4",
    "contact.nodes='tip'",
    "contact.surface=false",
    "contact.corners=false",
    "actuation.s_max=2.0",
    "actuation.period=1.0",
    "actuation.cycles=1",
    "actuation.settle_time=0.2",
]
PITCHES_MM = (2.0, 2.5, 3.0)

enable_compilation_cache()
base = load_spec("paper", QUICK)
advance_mm: dict[float, float] = {}
work_mJ: dict[float, float] = {}
for pitch in PITCHES_MM:
    # Grooves 1 mm wide, the first starting 0.5 mm right of each tip: both tips on lands.
    texture = Grooves(width=1.0, depth=0.25, pitch=pitch, phase=0.5, fillet_top=0.02)
    h = run(dataclasses.replace(base, substrate=texture))
    advance_mm[pitch] = float(h.net_advance)
    work_mJ[pitch] = float(h.connector_work[-1])


def main() -> None:
    for pitch in PITCHES_MM:
        print(
            f"pitch {pitch:.1f} mm: net advance {advance_mm[pitch]:+.4f} mm, "
            f"connector work {work_mJ[pitch]:.3f} mJ"
        )


if __name__ == "__main__":
    main()
