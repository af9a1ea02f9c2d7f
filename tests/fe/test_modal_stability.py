"""The modal analysis reports the sign of the tangent's eigenvalues.

A column under axial compression loses stiffness to its preload: for a cantilever the
lowest eigenvalue omega^2 falls with the load P and changes sign at Euler's load
P_cr = pi^2 EI / (4 L^2). Beyond it the straight state is an equilibrium that is not
stable; `modes` reports omega = 0 there and keeps the negative eigenvalue, which the
crawler's run uses to tell an unstable settled state from a free rigid-body mode.
"""

import math

import jax.numpy as jnp
import pytest

from bristlecrawler.fe import modes
from bristlecrawler.fe.static import StaticOptions, solve_static
from bristlecrawler.verification.cases import cantilever


def _lowest(load_ratio):
    m = cantilever(n=16)
    E, b, h = (float(m.params.sec[0, k]) for k in (0, 2, 3))
    p_cr = math.pi**2 * E * b * h**3 / 12.0 / 4.0  # L = 1 mm
    m = m.with_params(load_vec=jnp.asarray([[-load_ratio * p_cr, 0.0, 0.0]]))
    res = solve_static(m, options=StaticOptions(increments=1), check_support=False)
    md = modes(m, res.state.q, n_modes=1, t=float(res.state.t), lam=float(res.state.lam))
    return float(md.eigenvalues[0]), float(md.omega[0])


@pytest.mark.slow
def test_the_lowest_eigenvalue_falls_with_compression_and_turns_negative_past_euler():
    w0, om0 = _lowest(0.0)
    half, _ = _lowest(0.5)
    beyond, om_beyond = _lowest(1.5)
    assert w0 == pytest.approx(om0**2, rel=1e-9) and w0 > 0
    # omega^2 (P) ~ omega0^2 (1 - P / P_cr) for the cantilever's first mode (to a few %).
    assert half / w0 == pytest.approx(0.5, abs=0.05)
    assert beyond < 0 and om_beyond == 0.0
