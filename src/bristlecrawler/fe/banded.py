"""Bordered block-tridiagonal Jacobians: extraction by coloured JVPs and a linear solve.

A crawler is chains (bristles) hanging from a small rigid-body system. In the solver order of
:func:`structure._ordering` the tangent is

    [[A, B],      A: block tridiagonal (blocks bs x bs, bs >= half-bandwidth),
     [C, D]]      B, C, D: the few border DOFs (the body) and their couplings,

so a solve costs O(n bs^2 + n nb^2): linear in the number of elements.

*Extraction.* The interior couples DOFs at most ``bs`` apart in solver order (the block
size is the half-bandwidth, :func:`structure._ordering`), so the Jacobian of any residual
with this sparsity is recovered from 2 bs + 1 Jacobian-vector products: column j gets
colour j mod (2 bs + 1), and columns of one colour never share a row of the band
(Curtis, Powell & Reid 1974), plus nb JVPs for the border columns and nb VJPs for the
border rows. Cost is linear in n, and the residual is linearised once
(``jax.linearize``). (Colouring by block index mod 3 and position in the block needs
3 bs products; the band needs 2 bs + 1: 23 instead of 33 for the paper crawler.)

*Solve.* Block Thomas algorithm (block LU without pivoting between blocks, dense partial
pivoting within a block) in ``lax.scan``, then the Schur complement on the border.
Runs under ``jit`` and ``vmap``, on CPU and GPU.
"""

from __future__ import annotations

import jax
import jax.numpy as jnp
import numpy as np
import scipy.sparse as sp

from bristlecrawler._pytree import pytree


@pytree()
class BlockSystem:
    """lower/diag/upper: (n_blocks, bs, bs) (lower[0], upper[-1] are zero); B: (n_int_pad,
    nb); C: (nb, n_int_pad); D: (nb, nb). Padding rows/columns carry an identity."""

    lower: jax.Array
    diag: jax.Array
    upper: jax.Array
    B: jax.Array
    C: jax.Array
    D: jax.Array


def _colours(topo) -> int:
    return min(2 * topo.bs + 1, max(topo.n_interior, 1))


def _seeds(topo) -> np.ndarray:
    """Seed vectors (colours, n): interior column j in colour j mod (2 bs + 1)."""
    n, n_int, k = topo.n_red, topo.n_interior, _colours(topo)
    i = np.arange(n_int)
    seeds = np.zeros((k, n))
    seeds[i % k, i] = 1.0
    return seeds


def _pattern(topo, shift: int):
    """Where the entries of the blocks (I, I + shift) sit in the compressed products:
    (colour, row, inside the band), each (n_blocks, bs, bs) indexed [I, r, p]."""
    n_int, bs, nblk, k = topo.n_interior, topo.bs, topo.n_blocks, _colours(topo)
    I, r, p = np.meshgrid(np.arange(nblk), np.arange(bs), np.arange(bs), indexing="ij")
    row, col = I * bs + r, (I + shift) * bs + p
    band = (row < n_int) & (col >= 0) & (col < n_int) & (np.abs(row - col) <= bs)
    return np.where(band, col % k, 0), np.where(band, row, 0), band


def extract(fn, x, topo, t=None, dt=None):
    """``fn(x)`` and its Jacobian at ``x`` as a :class:`BlockSystem` (sparsity of ``topo``).

    With a time ``t`` (and its increment ``dt``), ``fn`` takes ``(x, t)`` and a third value
    is returned: the derivative of ``fn`` along ``t`` times ``dt``, from the same
    linearisation (one more seed), which a tangent predictor needs; the Newton loop then
    holds one copy of the linearised residual instead of two (half the compiled program).
    """
    n_int, nb, bs, nblk = topo.n_interior, topo.n_border, topo.bs, topo.n_blocks
    pad = nblk * bs - n_int
    timed = t is not None
    g = fn if timed else (lambda x, _t: fn(x))
    t = jnp.zeros((), x.dtype) if t is None else t
    y, f_jvp = jax.linearize(g, x, t)
    # One batch of tangents: the band's colours, the border columns, and the time seed.
    k = _colours(topo)
    seeds = [jnp.asarray(_seeds(topo)), jnp.eye(topo.n_red, dtype=x.dtype)[n_int:]]
    tseed = [jnp.zeros(k + nb, x.dtype)]
    if timed:
        seeds.append(jnp.zeros((1, topo.n_red), x.dtype))
        tseed.append(jnp.reshape(dt, (1,)).astype(x.dtype))
    Y = jax.vmap(f_jvp)(jnp.concatenate(seeds), jnp.concatenate(tseed))

    def pick(shift):
        colour, row, band = _pattern(topo, shift)
        return jnp.where(band, Y[colour, row], 0.0)  # [I, r, p]: Y[c, i] = J[i, col of c]

    diag = pick(0)
    pad_eye = np.zeros((nblk * bs,))
    pad_eye[n_int:] = 1.0
    diag = diag + jax.vmap(jnp.diag)(jnp.asarray(pad_eye.reshape(nblk, bs)))
    lower, upper = pick(-1), pick(1)
    if nb:
        cols = Y[k : k + nb]  # (nb, n): J[:, j] for the border columns j
        # The border rows J[j, :] by transposing the same linearisation (no second
        # forward pass of the residual, as jax.vjp would compile).
        f_vjp = jax.linear_transpose(f_jvp, x, t)
        E = jnp.eye(topo.n_red, dtype=x.dtype)[n_int:]
        rows = jax.vmap(lambda e: f_vjp(e)[0])(E)  # (nb, n)
        B = jnp.pad(cols[:, :n_int].T, ((0, pad), (0, 0)))
        C = jnp.pad(rows[:, :n_int], ((0, 0), (0, pad)))
        D = rows[:, n_int:]
    else:
        B = jnp.zeros((nblk * bs, 0))
        C = jnp.zeros((0, nblk * bs))
        D = jnp.zeros((0, 0))
    system = BlockSystem(lower, diag, upper, B, C, D)
    return (y, system, Y[-1]) if timed else (y, system)


def _thomas(system: BlockSystem, R):
    """Solve A X = R (R: (n_blocks, bs, k)) by block LU in two scans."""
    bs = system.diag.shape[-1]

    def fwd(carry, blocks):
        W_prev, Y_prev = carry
        L, Dg, U, r = blocks
        G = Dg - L @ W_prev
        sol = jnp.linalg.solve(G, jnp.concatenate([U, r - L @ Y_prev], axis=1))
        W, Yv = sol[:, :bs], sol[:, bs:]
        return (W, Yv), (W, Yv)

    k = R.shape[-1]
    init = (jnp.zeros((bs, bs)), jnp.zeros((bs, k)))
    _, (W, Yv) = jax.lax.scan(fwd, init, (system.lower, system.diag, system.upper, R))

    def bwd(X_next, blocks):
        Wi, Yi = blocks
        X = Yi - Wi @ X_next
        return X, X

    _, X = jax.lax.scan(bwd, jnp.zeros((bs, k)), (W, Yv), reverse=True)
    return X


def solve(system: BlockSystem, rhs, topo):
    """x with J x = rhs (reduced, solver order)."""
    n_int, nb, bs, nblk = topo.n_interior, topo.n_border, topo.bs, topo.n_blocks
    f = jnp.pad(rhs[:n_int], (0, nblk * bs - n_int))
    R = jnp.concatenate([f[:, None], system.B], axis=1).reshape(nblk, bs, 1 + nb)
    X = _thomas(system, R).reshape(nblk * bs, 1 + nb)
    xf = X[:, 0]
    if not nb:
        return xf[:n_int]
    XB = X[:, 1:]
    S = system.D - system.C @ XB
    y = jnp.linalg.solve(S, rhs[n_int:] - system.C @ xf)
    return jnp.concatenate([(xf - XB @ y)[:n_int], y])


def to_scipy(system: BlockSystem, topo) -> sp.csr_matrix:
    """The Jacobian as a scipy sparse matrix (numpy; modal analysis, checks, tests)."""
    n_int, nb, bs, nblk = topo.n_interior, topo.n_border, topo.bs, topo.n_blocks
    N = nblk * bs
    rows, cols, vals = [], [], []
    for shift, arr in ((-1, system.lower), (0, system.diag), (1, system.upper)):
        a = np.asarray(arr)
        I, r, p = np.meshgrid(np.arange(nblk), np.arange(bs), np.arange(bs), indexing="ij")
        J = I + shift
        ok = (J >= 0) & (J < nblk)
        rows.append((I * bs + r)[ok])
        cols.append((J * bs + p)[ok])
        vals.append(a[ok])
    rows, cols, vals = map(np.concatenate, (rows, cols, vals))
    A = sp.coo_matrix((vals, (rows, cols)), shape=(N, N)).tocsr()[:n_int, :n_int]
    if not nb:
        return A.tocsr()
    B = sp.csr_matrix(np.asarray(system.B)[:n_int])
    C = sp.csr_matrix(np.asarray(system.C)[:, :n_int])
    D = sp.csr_matrix(np.asarray(system.D))
    return sp.bmat([[A, B], [C, D]]).tocsr()
