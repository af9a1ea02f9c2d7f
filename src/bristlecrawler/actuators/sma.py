"""Lumped model of the prototype's shape-memory-alloy actuator under closed-loop control.

The crawler's body is shortened by a NiTi tension spring (20 active coils, outer diameter
6 mm, wire 0.75 mm; paper Section 2) against two rubber bands, and cooled by fans. The
cRIO's control (100 S/s) switches a 3.5 A current on until the shortening reaches s~, then
off until the crawler is back at its length, and repeats.

Model (units: mm, N, s, tonne, so energy in mJ and power in mW; temperature in deg C):

* Thermal: ``C dT/dt = R I^2 - hA (T - T_amb) + H m dxi/dt`` (Joule heating, forced
  convection, latent heat; dxi/dt < 0 on heating into austenite absorbs heat).
* Phase: martensite fraction xi with the cosine kinetics of Liang & Rogers (1990),
  hysteretic: heating converts between A_s and A_f, cooling between M_s and M_f.
* Mechanics (quasi-static): spring rate ``k_sma = G d^4 / (8 D^3 n)`` with the shear modulus
  mixed by phase, ``G = G_A + xi (G_M - G_A)``; the SMA spring force ``k_sma (u0 - s)`` balances
  the bands ``F_b0 + k_b s``; a mechanical stop keeps ``s >= 0``. The bristles' reaction
  (about F_p = 0.46 N) is neglected against the actuator forces (5-10 N).

The material constants are handbook values for NiTi; the convection coefficient and the
band preload were chosen so that the first cycle lasts about 20 s, as the paper reports.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from bristlecrawler.errors import InputError
from bristlecrawler.reduced.strokes import SampledStroke


@dataclass(frozen=True)
class SMAActuator:
    """Parameters of the SMA spring, antagonist bands, cooling and control.

    Attributes (units in brackets):
        wire_diameter [mm], coil_diameter (mean) [mm], active_coils [-],
        G_austenite, G_martensite [MPa]: shear moduli of NiTi,
        density [t/mm^3], specific_heat [mJ/(t K)], latent_heat [mJ/t],
        resistivity [ohm mm], h_conv [mW/(mm^2 K)]: forced-convection coefficient (fans),
        T_ambient, M_f, M_s, A_s, A_f [deg C],
        band_stiffness [N/mm], band_preload [N], spring_preextension u0 [mm],
        current [A]: on-current of the amplifier, s_target [mm]: s~, s_rest [mm]: "back at
        length" threshold, control_rate [samples/s].
    """

    wire_diameter: float = 0.75
    coil_diameter: float = 5.25
    active_coils: float = 20.0
    G_austenite: float = 25_000.0
    G_martensite: float = 8_000.0
    density: float = 6.45e-9
    specific_heat: float = 8.37e8
    latent_heat: float = 1.2e10
    resistivity: float = 8.0e-4
    h_conv: float = 0.15
    T_ambient: float = 22.0
    M_f: float = 30.0
    M_s: float = 40.0
    A_s: float = 45.0
    A_f: float = 60.0
    band_stiffness: float = 0.05
    band_preload: float = 5.0
    spring_preextension: float = 43.3
    current: float = 3.5
    s_target: float = 20.0
    s_rest: float = 0.05
    control_rate: float = 100.0

    def __post_init__(self) -> None:
        for name, value in self.__dict__.items():
            if not np.isfinite(value):
                raise InputError(f"SMA parameter {name} must be finite, got {value}")
        for name in (
            "wire_diameter",
            "coil_diameter",
            "active_coils",
            "G_austenite",
            "G_martensite",
            "density",
            "specific_heat",
            "resistivity",
            "h_conv",
            "band_stiffness",
            "current",
            "s_target",
            "control_rate",
        ):
            if getattr(self, name) <= 0:
                raise InputError(
                    f"SMA parameter {name} must be positive, got {getattr(self, name)}"
                )
        if not (self.M_f < self.M_s <= self.A_s < self.A_f):
            raise InputError("SMA transformation temperatures must satisfy M_f < M_s <= A_s < A_f")
        if self.s_target >= self.max_shortening:
            raise InputError(
                f"s_target {self.s_target:g} mm is beyond the actuator's reach "
                f"({self.max_shortening:.3g} mm in full austenite)"
            )

    @property
    def wire_length(self) -> float:
        """mm."""
        return np.pi * self.coil_diameter * self.active_coils

    @property
    def wire_area(self) -> float:
        """mm^2."""
        return 0.25 * np.pi * self.wire_diameter**2

    @property
    def mass(self) -> float:
        """t."""
        return self.density * self.wire_area * self.wire_length

    @property
    def heat_capacity(self) -> float:
        """mJ/K."""
        return self.mass * self.specific_heat

    @property
    def resistance(self) -> float:
        """ohm."""
        return self.resistivity * self.wire_length / self.wire_area

    @property
    def conductance(self) -> float:
        """Convective loss hA, mW/K."""
        return self.h_conv * np.pi * self.wire_diameter * self.wire_length

    def spring_rate(self, xi):
        """Spring rate at martensite fraction xi, N/mm (Wahl-free helical-spring formula)."""
        G = self.G_austenite + np.asarray(xi) * (self.G_martensite - self.G_austenite)
        return G * self.wire_diameter**4 / (8 * self.coil_diameter**3 * self.active_coils)

    def shortening(self, xi):
        """Quasi-static shortening (mm) at martensite fraction xi."""
        k = self.spring_rate(xi)
        s = (k * self.spring_preextension - self.band_preload) / (k + self.band_stiffness)
        return np.maximum(s, 0.0)

    @property
    def max_shortening(self) -> float:
        return float(self.shortening(0.0))


@dataclass(frozen=True)
class SMAResponse:
    """Time series of a closed-loop run (all sampled at the control rate).

    t [s], s [mm], current [A], temperature [deg C], xi [-], force [N] (actuator force).
    """

    t: np.ndarray
    s: np.ndarray
    current: np.ndarray
    temperature: np.ndarray
    xi: np.ndarray
    force: np.ndarray
    cycle_starts: np.ndarray

    def stroke(self) -> SampledStroke:
        """The shortening history, ready to drive the reduced (or FE) model."""
        return SampledStroke(self.t, self.s)

    @property
    def cycle_durations(self) -> np.ndarray:
        return np.diff(self.t[self.cycle_starts])


def _xi_update(p: SMAActuator, T: float, xi: float, heating: bool, xi0: float) -> float:
    if heating and T > p.A_s:
        target = (
            0.0 if T >= p.A_f else 0.5 * xi0 * (np.cos(np.pi * (T - p.A_s) / (p.A_f - p.A_s)) + 1)
        )
        return min(xi, target)
    if not heating and T < p.M_s:
        if T <= p.M_f:
            return 1.0
        target = 0.5 * (1 - xi0) * np.cos(np.pi * (T - p.M_f) / (p.M_s - p.M_f)) + 0.5 * (1 + xi0)
        return max(xi, target)
    return xi


def run_sma(
    p: SMAActuator | None = None, cycles: int = 5, substeps: int = 20, max_time: float = 1000.0
) -> SMAResponse:
    """Simulate the closed loop until ``cycles`` cycles are complete.

    The thermal ODE is integrated with ``substeps`` explicit sub-steps per control tick
    (stable: the thermal time constant is seconds, the sub-step 0.5 ms).
    """
    p = p or SMAActuator()
    if int(cycles) != cycles or cycles < 1:
        raise InputError(f"cycles must be an integer >= 1, got {cycles}")
    dt = 1.0 / p.control_rate
    h = dt / substeps
    C, R, hA, mH = p.heat_capacity, p.resistance, p.conductance, p.mass * p.latent_heat
    T, xi, xi0, heating, on = p.T_ambient, 1.0, 1.0, True, True
    ts, ss, cur, Ts, xis, fs, starts = [], [], [], [], [], [], [0]
    done, k = 0, 0
    while done < cycles:
        t = k * dt
        if t > max_time:
            raise InputError(f"SMA actuator did not complete {cycles} cycles in {max_time:g} s")
        s = float(p.shortening(xi))
        # Control law sampled at the control rate (as on the cRIO's FPGA).
        if on and s >= p.s_target:
            on = False
        elif not on and s <= p.s_rest:
            on = True
            done += 1
            starts.append(k)
        ts.append(t)
        ss.append(s)
        cur.append(p.current if on else 0.0)
        Ts.append(T)
        xis.append(xi)
        fs.append(float(p.band_preload + p.band_stiffness * s))
        power = 1e3 * R * (p.current if on else 0.0) ** 2  # W -> mW
        for _ in range(substeps):
            dT = (power - hA * (T - p.T_ambient)) * h / C
            T_new = T + dT
            now_heating = dT > 0
            if now_heating != heating:
                heating, xi0 = now_heating, xi
            xi_new = _xi_update(p, T_new, xi, heating, xi0)
            # Latent heat of the transformation that just happened (absorbed on heating).
            T = T_new + mH * (xi_new - xi) / C
            xi = xi_new
        k += 1
    idx = np.asarray(starts)
    return SMAResponse(
        np.asarray(ts),
        np.asarray(ss),
        np.asarray(cur),
        np.asarray(Ts),
        np.asarray(xis),
        np.asarray(fs),
        idx,
    )
