"""The results layer: what a crawler run, a design and a drag test give, typed, whatever
the model (FE crawler, reduced models, closed forms); the FE crawler, the reduced models,
the studies and the jobs all import it, and it imports only numpy.

* :class:`RunMetrics`: the motion of a run and its cost; :class:`RunSummary`: an FE run's
  summary numbers; :class:`DesignMetrics`: what a design study records of a design.
* :class:`DragSummary` (with :class:`Sliding`): what a drag test gives the reduced model;
  :class:`TextureLaw`: a bristle's resistance over its tip's position within a pitch.
* :mod:`.keys`: the JSON keys of them all, spelled once.

Every result has ``to_dict`` for JSON, units in the keys.
"""

from bristlecrawler.results import keys
from bristlecrawler.results.drag import DragSummary, Sliding, summary_of
from bristlecrawler.results.metrics import DESIGN_OUTPUTS, DesignMetrics, RunMetrics
from bristlecrawler.results.run import RunSummary
from bristlecrawler.results.texture import TextureLaw

__all__ = [
    "DESIGN_OUTPUTS",
    "DesignMetrics",
    "DragSummary",
    "RunMetrics",
    "RunSummary",
    "Sliding",
    "TextureLaw",
    "keys",
    "summary_of",
]
