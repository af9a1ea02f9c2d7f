"""HHT-alpha and Newmark: the scheme of the paper's ABAQUS model.

HHT-alpha (Hilber, Hughes & Taylor 1977; Hughes, *The Finite Element Method*, 2000,
Sec. 9.3.3), Abaqus sign convention alpha in [-1/3, 0] (default -0.05),
beta = (1 - alpha)^2 / 4, gamma = 1/2 - alpha:

    M a1 + (1 + alpha) r(u1, v1, t1) - alpha r(u0, v0, t0) = 0,
    r = C v + f_int(u) + sum_k r_k(u, v, t, h_k) - f_ext(t),
    u1 = u0 + dt v0 + dt^2 ((1/2 - beta) a0 + beta a1),  v1 = v0 + dt ((1 - gamma) a0 + gamma a1).

alpha = 0 is Newmark (beta, gamma free; 1/4, 1/2 = trapezoidal rule, energy conserving for
linear systems). Kinematics are integrated for the *full* nodal vectors and the constraints
(supports, rigid links, the actuated body) are imposed at t1 through u1 = expand(q1, t1);
the residual is projected by J^T = (d expand / dq)^T. This is the index-3 Lagrange-multiplier
HHT with the multipliers eliminated by the null-space (Jacobian) basis.
"""

from __future__ import annotations

import dataclasses

import jax
import jax.numpy as jnp

from bristlecrawler.errors import InputError
from bristlecrawler.fe import assembly
from bristlecrawler.fe.integrator import Integrator, element_masses, force
from bristlecrawler.fe.options import setting


@dataclasses.dataclass(frozen=True, init=False)
class HHT(Integrator, scheme="hht"):
    """HHT-alpha (alpha in [-1/3, 0]; 0 is Newmark): make it with
    :meth:`Integrator.hht` or :meth:`Integrator.newmark`; the coefficients' ranges are
    their declared settings'.

    Attributes:
        alpha: HHT's alpha (Abaqus sign convention), dimensionless.
        beta, gamma: Newmark's coefficients, dimensionless.

    Its start (:meth:`init`) is the force at the step's start and its scale, the same for
    every iterate and every step size from that state.
    """

    alpha: float = setting(-0.05, "HHT alpha, -", ge=-1.0 / 3.0, le=0.0)
    beta: float = setting(0.25 * 1.05**2, "Newmark beta, -", gt=0.0)
    gamma: float = setting(0.55, "Newmark gamma, -", ge=0.5)

    @classmethod
    def hht(cls, alpha: float = -0.05, **kw) -> HHT:
        """HHT-alpha, alpha in [-1/3, 0] (the setting's range): beta = (1 - alpha)^2 / 4,
        gamma = 1/2 - alpha."""
        return cls(alpha=alpha, beta=(1.0 - alpha) ** 2 / 4.0, gamma=0.5 - alpha, **kw)

    @classmethod
    def named(cls, alpha: float = -0.05, **kw) -> HHT:
        """:meth:`Integrator.of` ("hht"): HHT-alpha of ``alpha``."""
        return cls.hht(alpha, **kw)

    @classmethod
    def newmark(cls, beta: float = 0.25, gamma: float = 0.5, **kw) -> HHT:
        """Newmark (alpha = 0; beta > 0, gamma >= 1/2: the settings' ranges); the default
        (1/4, 1/2) is the trapezoidal rule."""
        return cls(alpha=0.0, beta=beta, gamma=gamma, **kw)

    def __post_init__(self) -> None:
        super().__post_init__()
        # alpha, beta and gamma are one scheme only together: a replace() of alpha alone
        # would keep alpha = -0.05's beta and gamma (not HHT-alpha, first order).
        if self.alpha != 0.0:
            beta, gamma = (1.0 - self.alpha) ** 2 / 4.0, 0.5 - self.alpha
            if abs(self.beta - beta) > 1e-12 or abs(self.gamma - gamma) > 1e-12:
                raise InputError(
                    f"HHT with alpha = {self.alpha:g} needs beta = {beta:.6g} and gamma = "
                    f"{gamma:.6g}, got {self.beta:.6g} and {self.gamma:.6g}: make it with "
                    "Integrator.hht(alpha)"
                )

    def init(self, state, params, topo, terms):
        masses = element_masses(params, topo)
        return force(state.u, state.v, state.t, state.history, params, topo, terms, masses=masses)

    def equations(self, state, start, params, dt, topo, terms):
        al, be, ga = self.alpha, self.beta, self.gamma
        t1 = state.t + dt
        u0, v0, a0 = state.u, state.v, state.a
        # Element masses once per step, not once per residual (three products M x each).
        Me = element_masses(params, topo)
        r0, s0 = start

        def newmark(u):
            a = (u - u0 - dt * v0) / (be * dt**2) - (0.5 / be - 1.0) * a0
            v = v0 + dt * ((1.0 - ga) * a0 + ga * a)
            return u, v, a

        def kin(q, tc=t1):
            # tc: time of the prescribed motions (supports, link stretches) in expand
            return newmark(assembly.expand(q, tc, 1.0, params, topo))

        def residual(q, tc=t1, freeze=False):
            # One expansion gives u and, transposed, the projection of the full residual.
            u, pull = jax.vjp(lambda q: assembly.expand(q, tc, 1.0, params, topo), q)
            u, v, a = newmark(u)
            r1, s1 = force(u, v, t1, state.history, params, topo, terms, freeze, Me)
            Ma = assembly.mass_times(a, params, topo, Me)
            full = Ma + (1.0 + al) * r1 - al * r0
            (R,) = pull(full)
            return R, jnp.linalg.norm(Ma) + s1 + jnp.abs(al) * s0

        return kin, residual
