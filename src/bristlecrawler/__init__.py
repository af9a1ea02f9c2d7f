"""bristlecrawler: crawlers that move by directional friction (Noselli & DeSimone).

Units throughout: mm, N, s, tonne (so stresses in MPa, energies in mJ = N mm).

Two models, two names:

* the reduced one-dimensional model (paper Section 4) is re-exported here:
  ``bc.simulate(bc.ReducedCrawler.two_bristle(), bc.Sin2Stroke(20.0, 20.0))``;
* the finite-element crawler (paper Section 3) is ``bc.crawler``:
  ``bc.crawler.run(bc.crawler.CrawlerSpec.paper())``, loaded (with JAX) on first use, like
  ``bc.fe``, ``bc.contact`` and ``bc.scenario``.
"""

from __future__ import annotations

__version__ = "0.1.0"

from bristlecrawler.errors import BristlecrawlerError, InputError, SolverError
from bristlecrawler.reduced import (
    Calibration,
    DirectionalFriction,
    ReducedCrawler,
    ReducedResult,
    SampledStroke,
    Sin2Stroke,
    TriangleStroke,
    breathing,
    calibrate,
    closed_form,
    peristaltic,
    read_history_csv,
    simulate,
    solve,
)

_LAZY = ("crawler", "fe", "contact", "scenario", "experiment", "actuators", "verification")


def __getattr__(name: str):
    # The FE layers import JAX (a second or more): load them when first used, so that
    # ``import bristlecrawler`` and the CLI's --help stay fast.
    if name in _LAZY:
        import importlib

        return importlib.import_module(f"bristlecrawler.{name}")
    raise AttributeError(f"module 'bristlecrawler' has no attribute {name!r}")


__all__ = [
    "BristlecrawlerError",
    "Calibration",
    "DirectionalFriction",
    "InputError",
    "ReducedCrawler",
    "ReducedResult",
    "SampledStroke",
    "Sin2Stroke",
    "SolverError",
    "TriangleStroke",
    "__version__",
    "breathing",
    "calibrate",
    "closed_form",
    "peristaltic",
    "read_history_csv",
    "simulate",
    "solve",
]
