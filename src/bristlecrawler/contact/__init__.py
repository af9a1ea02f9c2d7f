"""Frictional contact with rigid analytic substrates (2-D): geometry and constitutive kernels.

Public API (units: mm, N, s, mJ; everything float64 JAX, pure, jit/vmap/grad-able):

* substrates (frozen PyTree dataclasses, parameters as leaves): :class:`Flat`,
  :class:`Grooves`, :class:`Sawtooth`, :class:`Polyline`, their common form
  :class:`PeriodicProfile`; :data:`PAPER_GROOVES`, :data:`PAPER_MU`.
* geometry: :func:`project` -> :class:`Projection` (gap, normal, tangent, closest point,
  arc length), :func:`gap`, :func:`project_points` (jitted, many points).
* Friction laws: the abstract :class:`FrictionLaw` the contact kernels call (laws
  registered by name, :meth:`FrictionLaw.of`), :class:`CoulombLaw` and
  :class:`PowerLaw` (friction growing as a power of the load), :func:`return_map` ->
  :class:`CoulombStep`,
  :func:`incremental_potential`, :func:`generalized_forces`, :func:`normal_force`,
  :func:`normal_energy`, :func:`friction_potential`; states :data:`OPEN`, :data:`STICK`,
  :data:`SLIP`; :data:`PAPER_TIP_LOAD`; :data:`STICK_TOL` (the stick/slip tie).
* contact node on a substrate: :func:`node_potential`, :func:`node_force`, :func:`node_step`.

The TOML tables that describe substrates are validated in :mod:`bristlecrawler.scenario`.
"""

import bristlecrawler._x64  # noqa: F401  (float64 before any JAX code)
from bristlecrawler.contact.coulomb import (
    OPEN,
    PAPER_TIP_LOAD,
    SLIP,
    STICK,
    STICK_TOL,
    CoulombLaw,
    CoulombStep,
    FrictionLaw,
    friction_potential,
    generalized_forces,
    incremental_potential,
    normal_energy,
    normal_force,
    return_map,
)
from bristlecrawler.contact.node import node_force, node_potential, node_step
from bristlecrawler.contact.power_law import HERTZ_EXPONENT, PowerLaw
from bristlecrawler.contact.profile import PeriodicProfile, Projection, gap, project, project_points
from bristlecrawler.contact.substrates import (
    PAPER_GROOVES,
    PAPER_MU,
    Flat,
    Grooves,
    Polyline,
    Sawtooth,
    Substrate,
)

__all__ = [
    "HERTZ_EXPONENT",
    "OPEN",
    "PAPER_GROOVES",
    "PAPER_MU",
    "PAPER_TIP_LOAD",
    "SLIP",
    "STICK",
    "STICK_TOL",
    "CoulombLaw",
    "CoulombStep",
    "Flat",
    "FrictionLaw",
    "Grooves",
    "PeriodicProfile",
    "Polyline",
    "PowerLaw",
    "Projection",
    "Sawtooth",
    "Substrate",
    "friction_potential",
    "gap",
    "generalized_forces",
    "incremental_potential",
    "node_force",
    "node_potential",
    "node_step",
    "normal_energy",
    "normal_force",
    "project",
    "project_points",
    "return_map",
]
