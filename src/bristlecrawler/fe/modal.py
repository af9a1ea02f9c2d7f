"""Natural frequencies and modes about a (preloaded) equilibrium.

Generalised eigenproblem K_T phi = omega^2 M_r phi in the reduced unknowns, K_T the tangent
of the static residual at the state (geometric stiffness of the preload included), M_r =
J^T M J. Both are extracted in banded form and solved with scipy: dense ``eigh`` for small
models, shift-invert Lanczos (``eigsh``, sigma = 0) otherwise, so cost stays linear in n.
"""

from __future__ import annotations

import dataclasses
import functools

import jax
import jax.numpy as jnp
import numpy as np

from bristlecrawler.errors import SolverError
from bristlecrawler.fe import assembly, banded
from bristlecrawler.fe.programs import stored
from bristlecrawler.fe.static import tangent


@dataclasses.dataclass(frozen=True)
class Modes:
    """frequency_hz: (k,); omega: (k,) rad/s; shapes: (k, n_nodes, 3) full mode shapes
    (mass-normalised in the reduced unknowns); eigenvalues: (k,) omega^2 in rad^2/s^2
    with its sign. A negative eigenvalue is an unstable equilibrium (its omega and
    frequency are reported as 0), a zero one a free mode."""

    frequency_hz: np.ndarray
    omega: np.ndarray
    shapes: np.ndarray
    eigenvalues: np.ndarray


@functools.lru_cache(maxsize=64)
def mass_fn(topo):
    """The compiled mass matrix of ``topo``'s structure, ``fn(q, params, t, lam)``, in the
    reduced unknowns (tonne, tonne mm^2 for rotations); cached per topology."""

    @jax.jit
    def fn(q, params, t, lam):
        def expand(q):
            return assembly.expand(q, t, lam, params, topo)

        _, pull = jax.vjp(expand, q)

        def mass_red(w):
            return pull(assembly.mass_times(jax.jvp(expand, (q,), (w,))[1], params, topo))[0]

        return banded.extract(mass_red, jnp.zeros_like(q), topo)[1]

    return stored(fn, "fe.modal.mass", topo)


@functools.lru_cache(maxsize=64)
def _shapes_fn(topo):
    """Jitted ``(q, V, t, lam, params) -> (k, n_nodes, 3)``: full displacements of the
    reduced vectors ``V`` (k, n_red) about ``q``. Op by op (outside jit) the modal analysis
    of the paper crawler spent about 3.4 s compiling each primitive of ``expand``."""

    @jax.jit
    def fn(q, V, t, lam, params):
        def expand(q):
            return assembly.expand(q, t, lam, params, topo)

        return jax.vmap(lambda v: jax.jvp(expand, (q,), (v,))[1])(V)

    return stored(fn, "fe.modal.shapes", topo)


def mass_matrix(model, q, t: float = 0.0, lam: float = 1.0):
    """Reduced mass J^T M J at ``q`` as a :class:`banded.BlockSystem` (compiled)."""
    return mass_fn(model.topology)(
        jnp.asarray(q), model.params, jnp.asarray(float(t)), jnp.asarray(float(lam))
    )


def modes(model, q=None, n_modes: int = 3, t: float = 0.0, lam: float = 1.0, history=None) -> Modes:
    """The ``n_modes`` lowest modes at reduced state ``q`` (default: reference)."""
    import scipy.linalg as sla
    import scipy.sparse.linalg as spla

    topo = model.topology
    q = jnp.zeros(topo.n_red) if q is None else jnp.asarray(q)
    K = banded.to_scipy(tangent(model, q, t, lam, history), topo)
    M = banded.to_scipy(mass_matrix(model, q, t, lam), topo)
    K = 0.5 * (K + K.T)
    M = 0.5 * (M + M.T)
    k = min(n_modes, topo.n_red)
    try:
        if topo.n_red <= 600:
            w2, vec = sla.eigh(K.toarray(), M.toarray(), subset_by_index=(0, k - 1))
        else:
            w2, vec = spla.eigsh(K.tocsc(), k=k, M=M.tocsc(), sigma=0.0, which="LM")
            order = np.argsort(w2)
            w2, vec = w2[order], vec[:, order]
    except (np.linalg.LinAlgError, RuntimeError, ValueError) as exc:
        raise SolverError(f"modal analysis failed: {exc} (is the mass matrix singular?)") from exc
    omega = np.sqrt(np.clip(w2, 0.0, None))

    shapes = np.asarray(
        _shapes_fn(topo)(
            q, jnp.asarray(vec.T), jnp.asarray(float(t)), jnp.asarray(float(lam)), model.params
        )
    )
    return Modes(omega / (2.0 * np.pi), omega, shapes, np.asarray(w2))
