"""The crawler's solver settings: one object, the ``[solver]`` table of a scenario file.

Each setting is declared once here (name, default, meaning with its unit, valid range);
the scenario schema and ``bristlecrawler scenario keys`` are built from these
declarations, and the settings reach the FE kernels under the same names: the Newton
ones as :class:`fe.NewtonOptions`, the step rule as :class:`fe.StepControl`, the time
scheme as :class:`fe.Integrator`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

from bristlecrawler.errors import InputError
from bristlecrawler.fe.control import StepControl
from bristlecrawler.fe.hht import HHT
from bristlecrawler.fe.integrator import Integrator
from bristlecrawler.fe.newton import NewtonOptions
from bristlecrawler.fe.options import Settings, setting, setting_of


@dataclass(frozen=True)
class Solver(Settings):
    """Implicit dynamics (HHT-alpha, or backward Euler) with adaptive steps, and its
    Newton settings.

    The time-scheme, Newton and step-rule settings are :class:`fe.Integrator`'s (HHT's
    alpha), :class:`fe.NewtonOptions`'s and :class:`fe.StepControl`'s, declared again
    here with the crawler's narrower ranges;
    where the crawler's default differs from theirs, the declaration gives the reason
    (:func:`fe.options.own_defaults` lists them, the scenario guide shows them).
    """

    scheme: Literal["hht", "backward_euler"] = setting(
        "hht",
        "time scheme: 'hht' (HHT-alpha, second order, the paper's) or 'backward_euler' "
        "(first order, damps every mode: a quasi-static run; on `paper` the advance within "
        "0.03 %, 5 % more Newton iterations, its numerical damping outside the energy "
        "balance)",
        structural=True,
    )
    hht_alpha: float = setting_of(HHT, "alpha", structural=True)
    dt_max: float = setting(0.05, "largest time step, s", gt=0.0, le=1e3)
    dt_min: float = setting(
        1e-6, "smallest time step before giving up, s (at least 1e-12)", ge=1e-12, le=1e3
    )
    tolerance: float = setting_of(
        NewtonOptions,
        "tolerance",
        default=1e-8,
        why="the shipped scenarios and their checked results (the paper run's advance and "
        "work) are computed at 1e-8; the FE core's own cases keep 1e-9",
        doc="Newton tolerance on the relative residual, - (1e-15 to 0.1)",
        ge=1e-15,
        le=0.1,
        inf=False,
        structural=True,
    )
    max_iterations: int = setting_of(
        NewtonOptions,
        "max_iterations",
        default=25,
        why="12 saves iterations on `paper` but stopped `paper-vertical` at dt_min",
        doc="Newton iterations per step attempt before the step is cut (12 saves iterations "
        "on `paper` but stopped `paper-vertical` at dt_min)",
        ge=2,
        le=1000,
        structural=True,
    )
    stall_iterations: int = setting_of(
        NewtonOptions,
        "stall_iterations",
        doc="cut a step whose Newton goes this many iterations without halving its residual "
        "(0: off, only max_iterations)",
        le=1000,
        structural=True,
    )
    freeze_iterations: int = setting_of(
        NewtonOptions,
        "freeze_iterations",
        doc="Newton iterations of each step that keep every closed contact point in its last "
        "converged stick/slip status, ended early once that problem is solved; only later "
        "iterations, with the Coulomb return mapping, can converge (0: off). Must be below "
        "max_iterations",
        le=999,
        structural=True,
    )
    line_search: Literal["growth", "monotone"] = setting_of(
        NewtonOptions,
        "line_search",
        default="monotone",
        why="a contact point that flips between stick and slip from one iterate to the "
        "next makes growth cycle: one cycle of `paper` took 13,677 Newton iterations with "
        "it against 3,648; the FE core's growth keeps a slender beam's full Newton steps",
        doc="Newton line search: halve a correction until the residual decreases "
        "('monotone'), or only when it blows up ('growth')",
        structural=True,
    )
    predictor: Literal["tangent", "constant"] = setting_of(
        Integrator,
        "predictor",
        doc="start of each step's Newton: the residual linearised in the stroke's increment "
        "('tangent'), or the last converged state ('constant')",
        structural=True,
    )
    energy_tol: float = setting(
        1e-2,
        "largest energy one step may create, mJ: the changes of elastic, kinetic and "
        "potential energy and of the friction and damping dissipation over the step minus "
        "the connector work; a step above it is cut (inf: no control)",
        gt=0.0,
        inf=True,
        structural=True,
    )
    energy_loss_tol: float = setting(
        1e-2,
        "largest energy one step may lose, mJ (the same balance, the other sign): the "
        "impact-like loss of a large step across a snap. Bounded, the steps resolve the "
        "snaps; inf lets a step take a snap at once, which runs `paper` 2.3 times faster "
        "with the same advance, but lets the vertical bristles of `paper-vertical` flip "
        "over unresolved",
        gt=0.0,
        inf=True,
        structural=True,
    )
    max_correction: float = setting_of(
        NewtonOptions,
        "max_correction",
        default=0.05,
        why="capped, `paper` needs 16-22 % fewer Newton iterations for the same gait; "
        "the FE core leaves corrections uncapped",
        doc="largest nodal translation of a Newton correction's first trial, mm: a larger "
        "correction is scaled down to it before the line search halves it (inf: off). "
        "Corrections that moved a bristle tip by millimetres through the substrate took all "
        "the line search's halvings; capped, `paper` needs 16-22 % fewer Newton iterations "
        "for the same gait",
        structural=True,
    )
    grow: float = setting_of(StepControl, "grow", structural=True)
    easy_iterations: int = setting_of(StepControl, "easy_iterations", structural=True)

    def check(self, prefix: str = "solver.") -> None:
        super().check(prefix)

    def rules(self, prefix: str = "solver.") -> None:
        """InputError for an inconsistent pair (settings named with ``prefix``): the step
        bounds, or the Newton settings' own rules."""
        if self.dt_min >= self.dt_max:
            raise InputError(f"{prefix}dt_min must be smaller than {prefix}dt_max")
        if self.scheme != "hht" and self.hht_alpha != HHT.hht().alpha:
            raise InputError(
                f"{prefix}hht_alpha is HHT's: it has no meaning with {prefix}scheme = "
                f"{self.scheme!r}"
            )
        try:
            self.newton  # noqa: B018  (the Newton settings' own rules)
            self.integrator(math.inf)
        except InputError as e:
            raise InputError(f"{prefix}{e}") from None

    @property
    def newton(self):
        """The Newton settings of each step (:class:`fe.NewtonOptions`)."""
        return NewtonOptions(
            tolerance=self.tolerance,
            max_iterations=self.max_iterations,
            line_search=self.line_search,
            stall_iterations=self.stall_iterations,
            freeze_iterations=self.freeze_iterations,
            max_correction=self.max_correction,
        )

    @property
    def control(self):
        """The adaptive step rule (:class:`fe.StepControl`)."""
        return StepControl(self.grow, self.easy_iterations)

    def integrator(self, penetration_limit: float):
        """The :class:`fe.Integrator` of these settings (``hht_alpha`` only for HHT)."""
        own = {"alpha": self.hht_alpha} if self.scheme == "hht" else {}
        return Integrator.of(
            self.scheme,
            newton=self.newton,
            predictor=self.predictor,
            penetration_limit=penetration_limit,
            **own,
        )
