"""Nonlinear planar finite elements for the bristle crawler (paper Section 3), in JAX.

Corotational beams with tapered sections, point masses, rigid bodies, springs, rigid links
(with prescribed stretch: the actuated body), prescribed motions and dead loads; static
Newton with load stepping, modal analysis, HHT-alpha, Newmark and backward Euler dynamics
with adaptive steps.
Float64 throughout (:mod:`bristlecrawler._x64`). Units: mm, N, s, tonne (MPa, mJ).
"""

from __future__ import annotations

import bristlecrawler._x64  # noqa: F401  (float64 before any JAX code)
from bristlecrawler.fe.backward_euler import BackwardEuler
from bristlecrawler.fe.banded import BlockSystem
from bristlecrawler.fe.cache import enable_compilation_cache
from bristlecrawler.fe.control import StepControl
from bristlecrawler.fe.dynamics import (
    DynState,
    Rayleigh,
    energy,
    initial_state,
    make_step,
)
from bristlecrawler.fe.hht import HHT
from bristlecrawler.fe.integrator import Integrator
from bristlecrawler.fe.modal import Modes, modes
from bristlecrawler.fe.model import Model, Params, Topology
from bristlecrawler.fe.motion import Constant, Piecewise, Ramp, Sin2, Sine, TimeFunction
from bristlecrawler.fe.newton import NewtonOptions
from bristlecrawler.fe.static import (
    StaticOptions,
    StaticResult,
    StaticState,
    check_supported,
    solve_static,
)
from bristlecrawler.fe.status import StepInfo, check, message
from bristlecrawler.fe.stepping import SaveAt, Solution, Stepper, solve, stack
from bristlecrawler.fe.structure import Structure, TaperedRect
from bristlecrawler.fe.terms import Term

__all__ = [
    "HHT",
    "BackwardEuler",
    "BlockSystem",
    "Constant",
    "DynState",
    "Integrator",
    "Model",
    "Modes",
    "NewtonOptions",
    "Params",
    "Piecewise",
    "Ramp",
    "Rayleigh",
    "SaveAt",
    "Sin2",
    "Sine",
    "Solution",
    "StaticOptions",
    "StaticResult",
    "StaticState",
    "StepControl",
    "StepInfo",
    "Stepper",
    "Structure",
    "TaperedRect",
    "Term",
    "TimeFunction",
    "Topology",
    "check",
    "check_supported",
    "enable_compilation_cache",
    "energy",
    "initial_state",
    "make_step",
    "message",
    "modes",
    "solve",
    "solve_static",
    "stack",
]
