"""The bristled crawler: elastic bristles on the real texture, the body's own load path.

A design model between the paper's one-dimensional reduced model and the FE crawler, with
no FE in the loop (the model's equations, assumptions and limits:
``docs/guide/bristled-model.md``). Units: mm, N, s, tonne, mJ.

* :class:`TaperedBristle`, :class:`Chain`: a bristle and its two-joint elastic rod,
  calibrated in closed form against the tapered beam (:func:`elastica_tip` is the exact
  large-deflection reference).
* :class:`GroovedSurface`, :class:`PolylineSurface`, :class:`TipPath`: the substrate and
  where a bristle's tip can be on it.
* :class:`BristledDesign`, :func:`run` -> :class:`BristledResult`: a batch of designs
  played quasi-statically, stroke by stroke (:func:`play`: any sequence of shortenings).
"""

from bristlecrawler.reduced.bristled.elastica import elastica_tip
from bristlecrawler.reduced.bristled.model import (
    MODEL_NAME,
    BristledDesign,
    BristledResult,
    RunOptions,
    breathing_fractions,
    chain_of,
    path_of,
    play,
    run,
)
from bristlecrawler.reduced.bristled.path import GroovedSurface, PolylineSurface, TipPath
from bristlecrawler.reduced.bristled.rod import Chain, TaperedBristle

__all__ = [
    "MODEL_NAME",
    "BristledDesign",
    "BristledResult",
    "Chain",
    "GroovedSurface",
    "PolylineSurface",
    "RunOptions",
    "TaperedBristle",
    "TipPath",
    "breathing_fractions",
    "chain_of",
    "elastica_tip",
    "path_of",
    "play",
    "run",
]
