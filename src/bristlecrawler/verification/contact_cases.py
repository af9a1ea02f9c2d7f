"""Contact verification cases run through the FE solvers (issue: frictional contact).

Each case builds a small structure with the :class:`~bristlecrawler.contact.term.
SubstrateContact` term, runs the FE solver, and compares with the analytic references of
:mod:`bristlecrawler.verification.contact_refs` (computed independently of the FE code).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from bristlecrawler.verification.contact_refs import (
    DEFAULT_OSCILLATOR,
    OscillatorParams,
    coulomb_oscillator,
)


class OscillatorRun(NamedTuple):
    """FE Coulomb oscillator: turning points (mm), stop time (s), energy balance."""

    turning_points: np.ndarray
    stop_time: float
    dissipation: float
    energy_loss: float
    reference: object

    @property
    def energy_balance_rel_error(self) -> float:
        return abs(self.dissipation - self.energy_loss) / self.energy_loss


def coulomb_oscillator_fe(
    params: OscillatorParams = DEFAULT_OSCILLATOR, dt: float = 1e-3, t_end: float | None = None
) -> OscillatorRun:
    """Mass on a spring sliding on a flat Coulomb plane, trapezoidal rule (Newmark 1/4, 1/2).

    The normal penalty is sized for the weight (penetration 1 micrometre); the mass starts
    at rest at ``x0`` in vertical equilibrium, stuck where it is.
    """
    import jax.numpy as jnp

    from bristlecrawler import fe
    from bristlecrawler.contact import Flat
    from bristlecrawler.contact.coulomb import CoulombLaw
    from bristlecrawler.contact.term import SubstrateContact

    ref = coulomb_oscillator(params)
    weight = params.mass * params.gravity
    s = fe.Structure()
    anchor = s.node(-1e4, 0.0)  # a long spring: horizontal to first order
    s.fix(anchor)
    m = s.node(0.0, 0.0)
    s.fix(m, "theta")
    s.spring(anchor, m, params.stiffness)
    s.point_mass(m, params.mass)
    s.gravity(0.0, -params.gravity)
    law = CoulombLaw.for_reference_load(params.mu, load=weight)
    term = SubstrateContact((m,))
    X = np.array([[-1e4, 0.0], [0.0, 0.0]])
    s.add_term(term, SubstrateContact.params(X, (m,), Flat(), law))
    model = s.build()
    sink = -weight / float(law.k_n)
    u0 = jnp.zeros((2, 3)).at[m, 0].set(params.x0).at[m, 1].set(sink)
    state = fe.initial_state(
        model, q=jnp.array([params.x0, sink]), history=(term.history_at(u0, model.params.extra[0]),)
    )

    def observe(st):
        h = st.history[0]
        return float(st.u[m, 0]), float(st.v[m, 0]), int(h.state[0]), float(h.dissipation[0])

    t_end = t_end if t_end is not None else ref.stop_time + 0.5
    # HHT (alpha = -0.05) damps the stiff stick-penalty mode (omega dt ~ 3) that the
    # trapezoidal rule would keep ringing; at the oscillator's own frequency
    # (omega dt = 0.01) its numerical dissipation is negligible.
    res = fe.integrate(model, state, t_end, dt, integrator=fe.Integrator.hht(), observe=observe)
    obs = np.array(res.observed)
    x, v, _, diss = obs.T
    settled = np.abs(x - x[-1]) < 1e-3
    moving = np.flatnonzero(~settled)
    stop = float(res.times[moving[-1] + 1]) if moving.size else 0.0
    vtol = 1e-3 * params.omega * abs(params.x0)
    fast = np.abs(v) > vtol
    turns = [params.x0]
    last = None
    for i in np.flatnonzero(fast):
        sign = np.sign(v[i])
        if last is not None and sign != last:
            turns.append(float(x[i - 1 + int(np.argmin(np.abs(v[i - 1 : i + 1])))]))
        last = sign
    turns.append(float(x[-1]))
    tp = np.array(turns)
    loss = 0.5 * params.stiffness * (params.x0**2 - x[-1] ** 2)
    return OscillatorRun(tp, stop, float(diss[-1]), float(loss), ref)
