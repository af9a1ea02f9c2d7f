"""Nonlinear planar finite elements for the bristle crawler (paper Section 3), in JAX.

Corotational beams with tapered sections, point masses, rigid bodies, springs, rigid links
(with prescribed stretch: the actuated body), prescribed motions and dead loads; static
Newton with load stepping, modal analysis, Newmark / HHT-alpha dynamics with adaptive steps.
Float64 throughout (enabled here, once). Units: mm, N, s, tonne (MPa, mJ).
"""

from __future__ import annotations

import jax

jax.config.update("jax_enable_x64", True)

from bristlecrawler.fe.banded import BlockSystem  # noqa: E402
from bristlecrawler.fe.cache import enable_compilation_cache  # noqa: E402
from bristlecrawler.fe.drivers import (  # noqa: E402
    DriverCarry,
    driver_start,
    make_driver,
    make_host_driver,
)
from bristlecrawler.fe.dynamics import (  # noqa: E402
    DynResult,
    DynState,
    Integrator,
    Rayleigh,
    energy,
    initial_state,
    integrate,
    make_step,
    run_fixed,
)
from bristlecrawler.fe.modal import Modes, modes  # noqa: E402
from bristlecrawler.fe.model import Model, Params, Topology  # noqa: E402
from bristlecrawler.fe.motion import Constant, Ramp, Sin2, Sine, TimeFunction  # noqa: E402
from bristlecrawler.fe.static import (  # noqa: E402
    StaticOptions,
    StaticResult,
    StaticState,
    check_supported,
    solve_static,
)
from bristlecrawler.fe.status import StepInfo, check, message  # noqa: E402
from bristlecrawler.fe.structure import Structure, TaperedRect  # noqa: E402
from bristlecrawler.fe.terms import Term  # noqa: E402

__all__ = [
    "BlockSystem",
    "Constant",
    "DriverCarry",
    "DynResult",
    "DynState",
    "Integrator",
    "Model",
    "Modes",
    "Params",
    "Ramp",
    "Rayleigh",
    "Sin2",
    "Sine",
    "StaticOptions",
    "StaticResult",
    "StaticState",
    "StepInfo",
    "Structure",
    "TaperedRect",
    "Term",
    "TimeFunction",
    "Topology",
    "check",
    "check_supported",
    "driver_start",
    "enable_compilation_cache",
    "energy",
    "initial_state",
    "integrate",
    "make_driver",
    "make_host_driver",
    "make_step",
    "message",
    "modes",
    "run_fixed",
    "solve_static",
]
