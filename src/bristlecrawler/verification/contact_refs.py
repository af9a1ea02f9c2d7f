"""Analytic references for the frictional-contact verification cases.

Project units: mm, N, s, tonne (1 kg = 1e-3 t, g = 9810 mm/s^2, 100 N/m = 0.1 N/mm).

1. Coulomb oscillator (a mass on a spring sliding on a Coulomb plane): closed-form turning
   points and stop time (Den Hartog, Trans. ASME 53, 1931, "Forced vibrations with combined
   Coulomb and viscous friction"; Meirovitch, Elements of Vibration Analysis, Sec. 2.8), and
   an independent event-driven integrator of the same ODE to cross-check it.
2. Block on an incline pushed horizontally: push/weight ratio at the onset of sliding up.
3. Linearised elastic cantilever pressed on a flat plane and dragged: stick then slip.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from bristlecrawler.errors import InputError

#: Gravity, mm/s^2.
G_MM_S2 = 9810.0


def _positive(name: str, v: float) -> float:
    v = float(v)
    if not (math.isfinite(v) and v > 0):
        raise InputError(f"{name} must be a positive finite number, got {v!r}")
    return v


# --------------------------------------------------------------------------------------------
# 1. Coulomb oscillator
# --------------------------------------------------------------------------------------------


class OscillatorParams(NamedTuple):
    """Mass-spring on a Coulomb plane; defaults: 1 kg, 100 N/m, mu = 0.1, x0 = +100 mm.

    Attributes:
        mass: t (1 kg = 1e-3 t).
        stiffness: N/mm (100 N/m = 0.1 N/mm).
        mu: friction coefficient (static = kinetic), dimensionless.
        x0: initial position (released from rest), mm; the spring is unstretched at x = 0.
        gravity: mm/s^2.
    """

    mass: float = 1e-3
    stiffness: float = 0.1
    mu: float = 0.1
    x0: float = 100.0
    gravity: float = G_MM_S2

    @property
    def omega(self) -> float:
        """Natural circular frequency sqrt(k / m), rad/s."""
        return math.sqrt(_positive("stiffness", self.stiffness) / _positive("mass", self.mass))

    @property
    def stick_band(self) -> float:
        """Half-width of the stick band mu m g / k, mm: a turning point inside it is final."""
        return self.mu * self.mass * self.gravity / self.stiffness


#: The verification case of the brief: 1 kg, 100 N/m, mu = 0.1, released at +100 mm.
DEFAULT_OSCILLATOR = OscillatorParams()


class OscillatorHistory(NamedTuple):
    """Turning points of the Coulomb oscillator.

    Attributes:
        times: times of the turning points (the release first), s.
        positions: positions there, mm; the last one is where the mass stops.
        stop_time: time at which the mass comes to rest for good, s.
    """

    times: np.ndarray
    positions: np.ndarray
    stop_time: float


def coulomb_oscillator(params: OscillatorParams = DEFAULT_OSCILLATOR) -> OscillatorHistory:
    """Closed form: each half cycle (duration pi / omega) the amplitude drops by
    ``2 mu g / omega^2`` = twice the stick band, and the sign alternates; the mass stops at the
    first turning point with ``|x| <= mu m g / k``. Default case: 100, -80.38, 60.76, -41.14,
    21.52, -1.90 mm, stopping at t = 5 pi / 10 = 1.5708 s.
    """
    w = params.omega
    band = params.stick_band
    if band < 0:
        raise InputError(f"mu must be >= 0, got {params.mu}")
    a0 = abs(params.x0)
    if band == 0.0:
        raise InputError("mu = 0: the oscillator never stops (no finite turning-point list)")
    n_last = 0 if a0 <= band else math.ceil((a0 - band) / (2 * band))
    n = np.arange(n_last + 1)
    positions = math.copysign(1.0, params.x0) * (-1.0) ** n * (a0 - 2 * band * n)
    times = n * math.pi / w
    return OscillatorHistory(times=times, positions=positions, stop_time=float(times[-1]))


def coulomb_oscillator_position(
    t: np.ndarray, params: OscillatorParams = DEFAULT_OSCILLATOR
) -> np.ndarray:
    """Position x(t), mm, from the closed form (piecewise cosine about +-mu m g / k)."""
    hist = coulomb_oscillator(params)
    t = np.asarray(t, dtype=float)
    w = params.omega
    k = np.clip(np.floor(t * w / math.pi).astype(int), 0, len(hist.times) - 1)
    x_start = hist.positions[k]
    # While moving away from x_start the friction pushes towards x_start: equilibrium shifted.
    centre = np.sign(x_start) * params.stick_band
    x = centre + (x_start - centre) * np.cos(w * (t - hist.times[k]))
    return np.where(t >= hist.stop_time, hist.positions[-1], x)


def integrate_coulomb_oscillator(
    params: OscillatorParams = DEFAULT_OSCILLATOR, t_end: float = 10.0, rtol: float = 1e-11
) -> OscillatorHistory:
    """Independent reference: event-driven numerical integration of
    ``m x'' + k x + mu m g sign(x') = 0`` with ``scipy.integrate.solve_ivp`` (DOP853),
    stopping each phase when the velocity vanishes and testing stick with the static force.
    """
    from scipy.integrate import solve_ivp  # only the verification needs scipy

    m, k, mu, g = params.mass, params.stiffness, params.mu, params.gravity
    t, x, v = 0.0, float(params.x0), 0.0
    times, positions = [t], [x]
    while t < t_end:
        if abs(k * x) <= mu * m * g:  # static friction holds the spring force
            return OscillatorHistory(np.array(times), np.array(positions), t)
        direction = -math.copysign(1.0, x)  # released from rest: moves towards x = 0

        def rhs(_t, y, direction=direction):
            return [y[1], (-k * y[0] - direction * mu * m * g) / m]

        def stops(_t, y, direction=direction):
            return y[1] * direction

        stops.terminal, stops.direction = True, -1
        sol = solve_ivp(
            rhs, (t, t_end), [x, v], method="DOP853", events=stops, rtol=rtol, atol=1e-12
        )
        if not sol.t_events[0].size:
            break
        t = float(sol.t_events[0][0])
        x = float(sol.y_events[0][0][0])
        times.append(t)
        positions.append(x)
    return OscillatorHistory(np.array(times), np.array(positions), math.inf)


# --------------------------------------------------------------------------------------------
# 2. Block on an incline pushed horizontally
# --------------------------------------------------------------------------------------------


def incline_push_ratio(tan_angle: float = 0.1, mu: float = 0.3) -> float:
    """Horizontal push / weight at the onset of sliding up an incline,
    ``(tan a + mu) / (1 - mu tan a)`` (dimensionless). Default 0.4 / 0.97 = 0.41237.

    Raises InputError when ``mu tan a >= 1`` (the block wedges: no push slides it up).
    """
    if not mu >= 0:
        raise InputError(f"mu must be >= 0, got {mu}")
    den = 1.0 - mu * tan_angle
    if den <= 0:
        raise InputError(f"mu * tan(angle) = {mu * tan_angle} >= 1: the block self-locks")
    return (tan_angle + mu) / den


# --------------------------------------------------------------------------------------------
# 3. Elastic cantilever pressed and dragged on a flat plane (linearised)
# --------------------------------------------------------------------------------------------


def inclined_cantilever_compliance(
    length: float, bending_stiffness: float, axial_stiffness: float, alpha: float
) -> np.ndarray:
    """Tip compliance (mm/N) of a uniform Euler-Bernoulli cantilever in the (x, y) frame.

    The beam hangs from its clamp with its tip at ``clamp + L (sin alpha, -cos alpha)``
    (alpha from the vertical, rad; alpha > 0 leans the tip towards +x), so
    ``C = L/(EA) e_a e_a^T + L^3/(3 EI) e_b e_b^T`` with e_a the beam axis and e_b normal
    to it (Timoshenko & Gere, Mechanics of Materials, cantilever tip deflection).

    Args:
        length: L, mm. bending_stiffness: EI, N mm^2. axial_stiffness: EA, N.
        alpha: inclination from the vertical, rad.
    """
    L = _positive("length", length)
    ei = _positive("bending_stiffness", bending_stiffness)
    ea = _positive("axial_stiffness", axial_stiffness)
    e_a = np.array([math.sin(alpha), -math.cos(alpha)])
    e_b = np.array([math.cos(alpha), math.sin(alpha)])
    return L / ea * np.outer(e_a, e_a) + L**3 / (3 * ei) * np.outer(e_b, e_b)


class DragResult(NamedTuple):
    """Pressed-and-dragged cantilever, linearised.

    Attributes:
        drag_at_slip: horizontal clamp displacement at which slip starts, mm (>= 0;
            0 with ``slips_on_press`` when friction cannot even hold the pressing).
        normal_at_press: normal force after pressing, before dragging, N.
        friction_at_press: tangential force on the tip after pressing, N (+x positive).
        normal_in_slip: normal force during slip, N.
        friction_in_slip: magnitude of the friction force during slip, mu * normal, N.
        slips_on_press: the tip already slides while being pressed.
        self_locks: sliding in this direction is impossible (the linearised tip wedges:
            ``drag_at_slip`` and the slip forces are then ``inf``).
    """

    drag_at_slip: float
    normal_at_press: float
    friction_at_press: float
    normal_in_slip: float
    friction_in_slip: float
    slips_on_press: bool
    self_locks: bool = False


def cantilever_drag(
    compliance: np.ndarray, press: float, mu: float, direction: float = 1.0
) -> DragResult:
    """Stick-then-slip of a cantilever tip pressed on a rigid flat plane and dragged.

    The clamp is lowered by ``press`` (mm) with the tip held on the plane, then moved by
    ``h`` along ``direction`` (+1 or -1, x). In stick the tip is fixed, so its displacement
    relative to the clamp is ``u = (-direction h, press)`` and the force of the plane on the
    tip is ``f = K u`` with ``K = C^-1``. Slip starts when ``f_x = -direction mu f_y``:

        h* = press (mu K_yy + direction K_xy) / (K_xx + direction mu K_yx)

    In slip the tip slides with ``f = (-direction mu N, N)`` and its vertical displacement
    stays ``press``: ``N = press / (C_yy - direction mu C_yx)``.

    Args:
        compliance: (2, 2) tip compliance in the (horizontal, vertical) frame, mm/N.
        press: clamp lowering, mm (> 0, small: linearised).
        mu: friction coefficient.
        direction: +1 drag towards +x, -1 towards -x.
    """
    c = np.asarray(compliance, dtype=float)
    if c.shape != (2, 2) or not np.all(np.isfinite(c)):
        raise InputError(f"compliance must be a finite 2x2 matrix, got shape {c.shape}")
    if not np.allclose(c, c.T, rtol=1e-10, atol=0) or np.linalg.eigvalsh(c).min() <= 0:
        raise InputError("compliance must be symmetric positive definite")
    press = _positive("press", press)
    if not mu >= 0:
        raise InputError(f"mu must be >= 0, got {mu}")
    s = math.copysign(1.0, direction)
    k = np.linalg.inv(c)
    n0 = k[1, 1] * press
    t0 = k[0, 1] * press
    den_slip = c[1, 1] - s * mu * c[1, 0]
    den = k[0, 0] + s * mu * k[1, 0]
    slips_on_press = bool(abs(t0) > mu * n0)
    if den_slip <= 0 or (den <= 0 and not slips_on_press):
        # Friction cone and beam kinematics wedge the tip: no finite drag makes it slide.
        inf = math.inf
        return DragResult(inf, float(n0), float(t0), inf, inf, slips_on_press, True)
    n_slip = press / den_slip
    h = 0.0 if slips_on_press else press * (mu * k[1, 1] + s * k[0, 1]) / den
    return DragResult(
        float(h), float(n0), float(t0), float(n_slip), float(mu * n_slip), slips_on_press
    )
