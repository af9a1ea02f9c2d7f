"""Design studies: many designs of the reduced or the FE model, on Dask, resumable.

Public API (units in the output names: mm, mJ, N, s):

* :func:`load_study`, :class:`Study`, :func:`available_studies`: the study file (TOML).
* :func:`plan`: load, expand and validate a study (:class:`Plan`, its :class:`Designs`).
* :func:`run_sweep`, :class:`SweepOptions`: run or resume it; returns the summary.
* :func:`evaluate_fe`, :func:`evaluate_reduced`, :func:`evaluate_reduced_chunk`: one
  design (or a chunk) to its outputs (:data:`OUTPUTS`), :class:`DesignStatus`.
"""

from bristlecrawler.studies.designs import Base, Designs, expand, resolve_base
from bristlecrawler.studies.evaluate import (
    OUTPUTS,
    DesignStatus,
    evaluate_fe,
    evaluate_reduced,
    evaluate_reduced_chunk,
)
from bristlecrawler.studies.runner import Plan, SweepOptions, plan, run_sweep
from bristlecrawler.studies.schema import AxisRange, Study, available_studies, load_study

__all__ = [
    "OUTPUTS",
    "AxisRange",
    "Base",
    "DesignStatus",
    "Designs",
    "Plan",
    "Study",
    "SweepOptions",
    "available_studies",
    "evaluate_fe",
    "evaluate_reduced",
    "evaluate_reduced_chunk",
    "expand",
    "load_study",
    "plan",
    "resolve_base",
    "run_sweep",
]
