"""bristlecrawler: crawlers that move by directional friction (Noselli & DeSimone).

Units throughout: mm, N, s, tonne (so stresses in MPa, energies in mJ = N mm).

The reduced one-dimensional model is re-exported here; the finite-element layers live in
their sub-packages (``bristlecrawler.fe``, ``bristlecrawler.contact``) and import JAX.
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
