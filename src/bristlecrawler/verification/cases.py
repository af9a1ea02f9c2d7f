"""Verification cases of the FE core: FE results against :mod:`references`.

Every case returns :class:`Row` objects (case, quantity, reference, computed, error,
tolerance, pass). ``error`` is |computed - reference| / scale, with scale = |reference|
unless stated (positions that should vanish are scaled by L). Tolerances are the expected
size of the discretisation or solver error of each case, stated in the case's docstring.

Compile reuse: all cantilever cases share one mesh of ``N_ELEM`` elements (geometry,
sections, loads and tip mass are parameters, not topology), so one static program serves
them all.
"""

from __future__ import annotations

import dataclasses
import functools
import math

import jax.numpy as jnp
import numpy as np

from bristlecrawler.fe import (
    Integrator,
    StaticOptions,
    Stepper,
    Structure,
    TaperedRect,
    energy,
    initial_state,
    make_step,
    modes,
    solve_static,
)
from bristlecrawler.verification import references as ref

N_ELEM = 32
#: EI / (EA L^2) = h^2 / (12 L^2) of the verification cantilever (h = 0.01, L = 1).
EXTENSIBILITY = 0.01**2 / 12.0
LOADS = (1.0, 2.0, 5.0, 10.0)
#: The paper's bristle (Section 2): b = 30 mm, h 3 -> 0.5 mm, L = 5 mm, E = 1.1 MPa.
BRISTLE = {"E": 1.1, "b": 30.0, "h0": 3.0, "h1": 0.5, "L": 5.0}


@dataclasses.dataclass(frozen=True)
class Row:
    case: str
    quantity: str
    reference: float
    computed: float
    error: float
    tol: float

    @property
    def passed(self) -> bool:
        return bool(np.isfinite(self.error) and self.error <= self.tol)


def row(case, quantity, reference, computed, tol, scale=None) -> Row:
    """A row that passes when ``computed`` is within ``tol`` of ``reference``, relative
    to ``scale`` (default: the reference's size)."""
    scale = abs(reference) if scale is None else scale
    return Row(
        case,
        quantity,
        float(reference),
        float(computed),
        float(abs(computed - reference) / scale),
        tol,
    )


@functools.lru_cache(maxsize=8)
def cantilever(n: int = N_ELEM, L: float = 1.0, h: float = 0.01):
    """Uniform cantilever along +x (E = 1 MPa, b = 1 mm), clamped at node 0; the tip node
    carries a rigid body (mass 0) and a dead load (0), both set later as parameters."""
    s = Structure()
    nodes = s.chain((0.0, 0.0), (L, 0.0), n, TaperedRect(E=1.0, b=1.0, h0=h, rho=1.0))
    s.fix(nodes[0])
    s.rigid_body(nodes[-1], 0.0, 0.0)
    s.load(nodes[-1])
    return s.build()


def _EI(model) -> float:
    E, b, h = (float(model.params.sec[0, k]) for k in (0, 2, 3))
    return E * b * h**3 / 12.0


def _tip(result):
    return np.asarray(result.state.u)[-1]


def _static(model, **kw):
    # The support check compiles a tangent per mesh; these clamped meshes need none.
    return solve_static(
        model, options=StaticOptions(increments=kw.pop("increments", 1), **kw), check_support=False
    )


def tip_load_runs(n: int = N_ELEM, loads=LOADS) -> list[dict]:
    """FE cantilever under a perpendicular dead tip load, P L^2 / EI in ``loads``."""
    m = cantilever(n)
    out = []
    for lp in loads:
        mm = m.with_params(load_vec=jnp.asarray([[0.0, lp * _EI(m), 0.0]]))
        tip = _tip(_static(mm))
        out.append(
            {
                "PL2_EI": lp,
                "u_over_L": float(-tip[0]),
                "v_over_L": float(tip[1]),
                "theta": float(tip[2]),
            }
        )
    return out


def case_tip_load(runs=None) -> list[Row]:
    """Tip-loaded elastica; tol 1e-3: O(h^2) discretisation error at 32 elements."""
    runs = tip_load_runs() if runs is None else runs
    rows = []
    for r in runs:
        exact = ref.elastica_tip_load(r["PL2_EI"], EXTENSIBILITY)
        for q in ("u_over_L", "v_over_L", "theta"):
            rows.append(
                row("cantilever tip load", f"{q} @ PL2/EI={r['PL2_EI']:g}", exact[q], r[q], 1e-3)
            )
    return rows


def case_end_moment() -> list[Row]:
    """End moment M = 2 pi EI / L rolls the beam into a full circle: tip back at the clamp,
    tip rotation 2 pi. Constant moment is represented exactly by the element (the chords
    form a regular polygon), so tol 1e-8 (solver tolerance)."""
    m = cantilever()
    mm = m.with_params(load_vec=jnp.asarray([[0.0, 0.0, 2.0 * math.pi * _EI(m)]]))
    tip = _tip(_static(mm, increments=8))
    L = 1.0
    return [
        row("end moment (circle)", "tip x / L", 0.0, (L + tip[0]) / L, 1e-8, scale=1.0),
        row("end moment (circle)", "tip y / L", 0.0, tip[1] / L, 1e-8, scale=1.0),
        row("end moment (circle)", "tip rotation (rad)", 2.0 * math.pi, tip[2], 1e-8),
    ]


def _bristle(alpha: float):
    """The paper's bristle on the shared mesh, inclined ``alpha`` from the vertical."""
    m = cantilever()
    B = BRISTLE
    direction = np.array([math.sin(alpha), -math.cos(alpha)])
    X = np.outer(np.linspace(0.0, B["L"], N_ELEM + 1), direction)
    h = np.linspace(B["h0"], B["h1"], N_ELEM + 1)
    sec = np.column_stack(
        [
            np.full(N_ELEM, B["E"]),
            np.full(N_ELEM, B["E"] / 2.9),
            np.full(N_ELEM, B["b"]),
            h[:-1],
            h[1:],
            np.zeros(N_ELEM),
        ]
    )
    return m.with_params(X=jnp.asarray(X), sec=jnp.asarray(sec))


def bristle_stiffness(alpha: float, direction=(1.0, 0.0)) -> float:
    """FE small-load tip stiffness (N/mm) along ``direction``: tangent solve about the
    reference (a finite load on the inclined bristle would add its geometric stiffness,
    P L^2 / EI_tip ~ 1e-2 per 1e-4 N, and round-off limits how small it can be)."""
    from bristlecrawler.fe.static import linear_solve

    m = _bristle(alpha)
    d = np.asarray(direction)
    f = jnp.zeros((m.topology.n_nodes, 3)).at[-1, :2].set(jnp.asarray(d))
    return float(1.0 / (np.asarray(linear_solve(m, f))[-1, :2] @ d))


def case_bristle() -> tuple[list[Row], dict]:
    """Tapered bristle, shear off: tip stiffness (vertical bristle, load across) and
    horizontal stiffness at alpha = pi/4 with axial compliance. The element flexibility is
    exact up to 8-point quadrature of 1/EI: tol 1e-6."""
    B = BRISTLE
    args = (B["E"], B["b"], B["h0"], B["h1"], B["L"])
    k_tip = bristle_stiffness(0.0)
    k_h = bristle_stiffness(math.pi / 4.0)
    rows = [
        row(
            "tapered bristle",
            "tip stiffness (N/mm)",
            1.0 / ref.tapered_bending_compliance(*args),
            k_tip,
            1e-6,
        ),
        row(
            "tapered bristle",
            "horizontal stiffness, alpha=pi/4 (N/mm)",
            ref.inclined_horizontal_stiffness(*args, math.pi / 4.0),
            k_h,
            1e-6,
        ),
    ]
    return rows, {
        "tapered_tip_stiffness_N_per_mm": k_tip,
        "bristle_horizontal_stiffness_N_per_mm": k_h,
    }


def case_tip_mass_frequency(mass_ratio: float = 1.0) -> list[Row]:
    """First frequency of a cantilever with a tip mass mu rho A L, mu = 1. Reference ignores
    rotary inertia (here (h/L)^2/12 ~ 1e-5); mass is interpolated linearly: O(h^2) error,
    tol 1e-3 at 32 elements."""
    m = cantilever()
    rhoA = float(m.params.rho[0] * m.params.sec[0, 2] * m.params.sec[0, 3])
    mt = mass_ratio * rhoA * 1.0
    mass = jnp.zeros_like(m.params.node_mass).at[-1].set(jnp.asarray([mt, mt, 0.0]))
    f_fe = modes(m.with_params(node_mass=mass), n_modes=1).frequency_hz[0]
    beta = ref.tip_mass_beta(mass_ratio)
    f_ref = beta**2 * math.sqrt(_EI(m) / (rhoA * 1.0**4)) / (2.0 * math.pi)
    return [row("tip-mass cantilever", "f1 (Hz)", f_ref, f_fe, 1e-3)]


def case_energy(n_steps: int = 1000) -> list[Row]:
    """Trapezoidal rule (Newmark 1/4, 1/2), undamped cantilever released from a small static
    deflection (linear regime, where the rule conserves energy exactly), dt = T1/20:
    max relative energy drift over ``n_steps`` must stay below 1e-6."""
    m = cantilever()
    EI = _EI(m)
    pre = m.with_params(load_vec=jnp.asarray([[0.0, 1e-6 * EI, 0.0]]))
    # The tip-load cases' compiled solver (rtol 1e-10): the drift is measured from s0
    # itself, so how tightly q0 balances the preload does not enter.
    q0 = _static(pre).state.q
    free = m.with_params(load_vec=jnp.zeros((1, 3)))
    s0 = initial_state(free, q=q0)
    rhoA = float(m.params.rho[0] * m.params.sec[0, 2] * m.params.sec[0, 3])
    dt = 2.0 * math.pi / (1.8751**2 * math.sqrt(EI / rhoA)) / 20.0
    ig = Integrator.newmark(0.25, 0.5, tolerance=1e-12)
    chunk = 100
    E0 = energy(s0, free)["total"]
    drift, s = 0.0, s0
    for _ in range(n_steps // chunk):
        s, infos = Stepper.of(free, integrator=ig).fixed(s, free.params, dt, chunk)
        if not np.all(np.asarray(infos.status) == 0):
            drift = float("inf")
            break
        drift = max(drift, abs(energy(s, free)["total"] - E0) / E0)
    return [Row("trapezoidal energy", f"max |dE|/E0 over {n_steps} steps", 0.0, drift, drift, 1e-6)]


@functools.lru_cache(maxsize=1)
def oscillator():
    """Unit mass on a unit spring along x (y, theta fixed): x'' + x = 0, linear while the
    spring (rest length 10) stays in tension side of zero length, i.e. |x| < 10."""
    s = Structure()
    a = s.node(0.0, 0.0)
    b = s.node(10.0, 0.0)
    s.fix(a)
    s.fix(b, ("y", "theta"))
    s.spring(a, b, 1.0)
    s.point_mass(b, 1.0)
    return s.build()


def measured_roots(integrator: Integrator, Omega: float, n: int = 40) -> tuple[float, float]:
    """Spectral radius and damping ratio of a scheme, measured on the FE oscillator.

    The discrete solution x_n obeys the scheme's 3-term recurrence exactly; it is fitted by
    least squares and its characteristic roots give (rho, xi) with :func:`principal_roots`.
    """
    m = oscillator()
    step = make_step(m.topology, m.terms, integrator)
    s = initial_state(m, q=jnp.asarray([1e-2]))
    xs = [float(s.u[1, 0])]
    for _ in range(n):
        s, _info = step(s, m.params, jnp.asarray(Omega))
        xs.append(float(s.u[1, 0]))
    x = np.asarray(xs)
    A = np.column_stack([x[2:-1], x[1:-2], x[:-3]])
    c = np.linalg.lstsq(A, x[3:], rcond=None)[0]
    return ref.principal_roots(np.roots([1.0, -c[0], -c[1], -c[2]]))


def case_hht(alpha: float = -0.05) -> list[Row]:
    """HHT numerical dissipation on a linear oscillator vs the amplification matrix: rho and
    xi at Omega = 0.5, 2 (tol 1e-6, round-off of the fit), and the high-frequency limit
    rho_inf = (1 + alpha)/(1 - alpha) at Omega = 1e3 (tol 1e-3, finite Omega)."""
    ig = Integrator.hht(alpha, tolerance=1e-13)
    rows = []
    for Om in (0.5, 2.0):
        rho, xi = measured_roots(ig, Om)
        rho_t, xi_t = ref.principal_roots(
            np.linalg.eigvals(ref.hht_amplification(ig.alpha, ig.beta, ig.gamma, Om))
        )
        rows.append(row("HHT dissipation", f"spectral radius @ Omega={Om:g}", rho_t, rho, 1e-6))
        rows.append(row("HHT dissipation", f"damping ratio @ Omega={Om:g}", xi_t, xi, 1e-6))
    rho_inf = measured_roots(ig, 1e3, n=12)[0]
    rows.append(
        row("HHT dissipation", "rho_inf (Omega=1e3)", (1 + alpha) / (1 - alpha), rho_inf, 1e-3)
    )
    return rows


def convergence(sizes=(4, 8, 16, 32), load: float = 2.0) -> dict:
    """Tip deflection error of the tip-loaded elastica vs element count; observed order
    p = log2(e_n / e_2n) of the last halving."""
    exact = ref.elastica_tip_load(load, EXTENSIBILITY)["v_over_L"]
    errs = [abs(tip_load_runs(n, (load,))[0]["v_over_L"] - exact) for n in sizes]
    orders = [
        math.log(errs[i] / errs[i + 1]) / math.log(sizes[i + 1] / sizes[i])
        for i in range(len(sizes) - 1)
    ]
    return {"sizes": list(sizes), "errors": errs, "orders": orders}


def case_convergence(conv=None) -> list[Row]:
    """Observed order of the tip deflection error (reference 2, tol 0.1 relative)."""
    conv = convergence() if conv is None else conv
    return [
        row(
            "mesh convergence",
            f"order v/L, n={conv['sizes'][-2]}->{conv['sizes'][-1]}",
            2.0,
            conv["orders"][-1],
            0.1,
        )
    ]
