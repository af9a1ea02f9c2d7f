"""Reduced one-dimensional model of directional crawling (paper Section 4), generalised.

Public API (units: mm, N, s, mJ):

* :class:`DirectionalFriction`: the friction law, eq. (4.1).
* :class:`ReducedCrawler`: N bristles on a body of N-1 actuated segments.
* strokes :class:`Sin2Stroke`, :class:`TriangleStroke`, :class:`SampledStroke`,
  :func:`read_history_csv`; gaits :func:`breathing`, :func:`peristaltic`.
* :func:`simulate` / :func:`solve`: the exact rate-independent solver -> :class:`ReducedResult`.
* :mod:`closed_form`: two-bristle closed forms in all regimes (vectorised).
* :func:`calibrate`: F_p/k, F_p, k from advance and work.
* :class:`RunMetrics`, :class:`DesignMetrics`, :class:`DragSummary`, :class:`TextureLaw`:
  the typed results of :mod:`bristlecrawler.results`, shared with the FE crawler, here
  too for convenience.
* :class:`TexturedCrawler`: N bristles on a :class:`TextureLaw` (``simulate`` solves it
  exactly);
  :mod:`textured_pair`: two-bristle designs in batches.
"""

from bristlecrawler.reduced import closed_form
from bristlecrawler.reduced.calibration import Calibration, calibrate
from bristlecrawler.reduced.crawler import (
    DEFAULT_FN_OVER_FP,
    PAPER_CYCLES,
    PAPER_FP,
    PAPER_K,
    PAPER_LENGTH,
    PAPER_PERIOD,
    PAPER_S_MAX,
    ReducedCrawler,
)
from bristlecrawler.reduced.friction import DirectionalFriction
from bristlecrawler.reduced.gaits import Gait, breathing, peristaltic
from bristlecrawler.reduced.simulate import simulate
from bristlecrawler.reduced.solver import (
    SLIP_BACKWARD,
    SLIP_FORWARD,
    SLIP_NONE,
    Event,
    ReducedResult,
    solve,
)
from bristlecrawler.reduced.strokes import (
    SampledStroke,
    Sin2Stroke,
    TriangleStroke,
    read_history_csv,
)
from bristlecrawler.reduced.textured import TexturedCrawler
from bristlecrawler.results.drag import DragSummary
from bristlecrawler.results.metrics import DesignMetrics, RunMetrics
from bristlecrawler.results.texture import TextureLaw

__all__ = [
    "DEFAULT_FN_OVER_FP",
    "PAPER_CYCLES",
    "PAPER_FP",
    "PAPER_K",
    "PAPER_LENGTH",
    "PAPER_PERIOD",
    "PAPER_S_MAX",
    "SLIP_BACKWARD",
    "SLIP_FORWARD",
    "SLIP_NONE",
    "Calibration",
    "DesignMetrics",
    "DirectionalFriction",
    "DragSummary",
    "Event",
    "Gait",
    "ReducedCrawler",
    "ReducedResult",
    "RunMetrics",
    "SampledStroke",
    "Sin2Stroke",
    "TextureLaw",
    "TexturedCrawler",
    "TriangleStroke",
    "breathing",
    "calibrate",
    "closed_form",
    "peristaltic",
    "read_history_csv",
    "simulate",
    "solve",
]
