"""The time integrator as a solver object: the seam between a scheme and the steppers.

An :class:`Integrator` says what one time step solves; the steppers (:func:`fe.solve` and
the drivers behind it) only ask it, through two hooks:

* :meth:`Integrator.init` ``(state, params, topo, terms) -> start``: what every step from
  ``state`` shares, whatever its size and iterate (HHT: the force at the step's start);
  a batched loop keeps it per design while that design's step is pending.
* :meth:`Integrator.equations` ``(state, start, params, dt, topo, terms) -> (kin,
  residual)``: ``kin(q, tc)`` the full (u, v, a) at the step's end for reduced unknowns
  ``q`` (prescribed motions at time ``tc``, default the step's end), and ``residual(q, tc,
  freeze) -> (R, F)`` the step's equations in the reduced unknowns and their force scale
  (N), which Newton solves.

The settings every scheme shares (Newton's, the predictor, the checks of a converged
state) live on the base class. Adding a scheme is one file: a frozen dataclass subclass
with its own coefficients and the two hooks (:mod:`.hht`, :mod:`.backward_euler`).
"""

from __future__ import annotations

import abc
import dataclasses
import math
from typing import ClassVar, Literal

import jax.numpy as jnp

from bristlecrawler.errors import InputError
from bristlecrawler.fe import assembly
from bristlecrawler.fe.newton import DEFAULT_NEWTON, NewtonOptions
from bristlecrawler.fe.options import check_settings, compose, renamed, setting


def force(u, v, t, history, params, topo, terms, freeze=False, masses=None):
    """r = C v + f_int + terms - f_ext (full, N) and its force scale (N): the forces every
    scheme balances against inertia (``freeze``: :func:`assembly.terms_residual`;
    ``masses``: :func:`assembly.element_masses` where already computed)."""
    f_int, damp = assembly.internal_and_damping_force(u, v, params, topo, masses)
    f_t = assembly.terms_residual(u, v, t, history, params, terms, freeze)
    f_ext = assembly.external_force(t, 1.0, params, topo, masses)
    scale = sum(jnp.linalg.norm(x) for x in (f_int, damp, f_t, f_ext))
    return damp + f_int + f_t - f_ext, scale


def element_masses(params, topo):
    """The element masses of ``topo`` (None without elements), once per step rather than
    once per residual."""
    return assembly.element_masses(params, topo) if topo.elems else None


@renamed(max_penetration="penetration_limit")
@dataclasses.dataclass(frozen=True, init=False)
class Integrator(abc.ABC):
    """A time integration scheme and the settings of its steps (static: part of the
    compiled step, so hashable).

    Make one with :meth:`hht` (default alpha = -0.05), :meth:`newmark` or
    :meth:`backward_euler`; each takes the Newton settings as ``newton=NewtonOptions(...)``
    or as keywords of the same names (``Integrator.hht(tolerance=1e-12,
    max_iterations=8)``). Their meanings are :class:`NewtonOptions`'s; in a step, the
    convergence test's force scale F is the sum of the inertial, internal, damping and
    external force norms (N), ``stall_iterations`` and a failed line search cut the step,
    and ``freeze_iterations`` counts the predictor. ``max_correction`` does not cap the
    predictor; with ``predictor="constant"`` it caps the first correction.

    Attributes:
        newton: the Newton settings of each step (:class:`NewtonOptions`).
        predictor: "tangent" (default) starts Newton from q0 + dq with J dq = -(R + dR/dt
            dt), the residual *linearised* in the step's change of the prescribed motions
            (supports, link stretches); "constant" starts from the last converged q.
        penetration_limit: a converged step whose committed contact state has a
            penetration deeper than this (mm; terms that report one, see :mod:`.terms`)
            is rejected with status PENETRATION, so an adaptive driver cuts it (default:
            no limit).
        max_rotation: largest nodal rotation change (rad) accepted in one step: rotations
            enter the energy only modulo 2 pi, so Newton can converge to a state with a
            node turned by about 2 pi (a kick of spurious kinetic energy); such a step is
            rejected with status ROTATION_LIMIT and cut.
    """

    newton: NewtonOptions = DEFAULT_NEWTON
    predictor: Literal["tangent", "constant"] = setting(
        "tangent",
        "start of each step's Newton: the residual linearised in the step's change of the "
        "prescribed motions ('tangent'), or the last converged state ('constant')",
    )
    penetration_limit: float = setting(
        math.inf, "deepest contact penetration of a converged step, mm", gt=0.0, inf=True
    )
    max_rotation: float = setting(
        1.0, "largest nodal rotation change in one step, rad", gt=0.0, inf=True
    )

    def __init__(self, newton=None, **settings):
        own = {f.name for f in dataclasses.fields(self)} - {"newton"}
        given = {k: settings.pop(k) for k in list(settings) if k in own}
        newton = DEFAULT_NEWTON if newton is None else newton
        if not isinstance(newton, NewtonOptions):
            raise InputError(f"newton must be a NewtonOptions, got {newton!r}")
        newton = compose(type(self).__name__, {"newton": newton}, settings)["newton"]
        for f in dataclasses.fields(self):
            value = newton if f.name == "newton" else given.get(f.name, f.default)
            object.__setattr__(self, f.name, value)
        self.__post_init__()

    def __post_init__(self) -> None:
        check_settings(self)  # the scheme's own coefficients too

    # -- the two hooks of a scheme ------------------------------------------------------

    @abc.abstractmethod
    def init(self, state, params, topo, terms):
        """What every step from ``state`` shares (a PyTree of arrays; ``()`` for none)."""

    @abc.abstractmethod
    def equations(self, state, start, params, dt, topo, terms):
        """``(kin, residual)`` of one step of ``dt`` (s) from ``state`` (see the module)."""

    # -- the schemes by name ------------------------------------------------------------
    # A scheme's module registers its class (``class HHT(Integrator, scheme="hht")``), so
    # the base class names them without importing them.

    _schemes: ClassVar[dict[str, type]] = {}

    def __init_subclass__(cls, scheme: str | None = None, **kw):
        super().__init_subclass__(**kw)
        if scheme is not None:
            Integrator._schemes[scheme] = cls

    @classmethod
    def of(cls, name: str, **kw) -> Integrator:
        """The scheme registered as ``name`` ("hht", "backward_euler", ...) with the
        settings ``kw`` (its own and Newton's, as its classmethod takes them)."""
        if name not in Integrator._schemes:
            known = ", ".join(sorted(Integrator._schemes))
            raise InputError(f"no time scheme named {name!r}: the schemes are {known}")
        return Integrator._schemes[name].named(**kw)

    @classmethod
    def named(cls, **kw) -> Integrator:
        """This scheme with the settings ``kw`` (:meth:`of`; a scheme whose coefficients
        go together, as HHT's, makes them here)."""
        return cls(**kw)

    @classmethod
    def hht(cls, alpha: float = -0.05, **kw) -> Integrator:
        """HHT-alpha (:class:`.hht.HHT`), alpha in [-1/3, 0]."""
        return Integrator._schemes["hht"].hht(alpha, **kw)

    @classmethod
    def newmark(cls, beta: float = 0.25, gamma: float = 0.5, **kw) -> Integrator:
        """Newmark (:class:`.hht.HHT` with alpha = 0); the default (1/4, 1/2) is the
        trapezoidal rule."""
        return Integrator._schemes["hht"].newmark(beta, gamma, **kw)

    @classmethod
    def backward_euler(cls, **kw) -> Integrator:
        """Backward Euler (:class:`.backward_euler.BackwardEuler`): first order, L-stable."""
        return Integrator._schemes["backward_euler"](**kw)
