"""Newton-Raphson with backtracking line search, jit/vmap friendly (``lax.while_loop``).

Tangent by coloured JVPs of the residual (:func:`banded.extract`), solve by the bordered
block-tridiagonal algorithm. Line search is a safeguard: the step is
halved (at most ``max_backtracks`` times) while the trial residual is NaN/inf or larger than
``growth`` (1e6) times the current one, i.e. only against blow-ups. Monotone merits were
tried and rejected: Armijo on |R|^2, Crisfield's energy-slope search (Crisfield 1991,
Sec. 9.3) and Deuflhard's natural monotonicity test all cut the good full Newton steps of a
slender beam (from the straight cantilever the full step overshoots in axial strain by a
factor ~1e4 in |R|, and the next step removes it), and Newton then needed 30-45 iterations
instead of 6-8 for P L^2/EI = 1..10. Robustness comes from the adaptive load / time steps.
Converged when |R| <= rtol F + atol, F the force scale returned by the residual.
"""

from __future__ import annotations

import jax
import jax.numpy as jnp

from bristlecrawler.fe import banded
from bristlecrawler.fe.status import MAX_ITERATIONS, NONFINITE, STALLED, SUCCESS


def newton(
    residual,
    q0,
    topo,
    *,
    rtol,
    atol,
    max_iter,
    xscale=0.0,
    xtol=1e-13,
    max_backtracks=8,
    growth=1e6,
    monotone=False,
    stall=0,
):
    """Solve residual(q)[0] = 0 from ``q0``. Returns (q, iterations, |R|, F, status).

    Also converged when the last correction is below ``xtol`` max(|q|, ``xscale``) (xscale:
    size of the structure, mm): the iterate has stopped moving at round-off. The residual
    has a floor of about |K| eps |X| (stiffness times the float64 spacing of the node
    coordinates), which for a small load on a stiff member (the paper's bristle under
    1e-4 N) is far above rtol F. The achieved |R|/F is reported either way.

    Each correction is halved (up to ``max_backtracks`` times) while the new residual is
    not finite or exceeds ``growth`` times the current one; with ``monotone`` (static,
    part of the compiled program) while it does not decrease at all. The monotone search
    breaks the cycle of a contact point that flips between stick and slip from one
    iterate to the next (a friction force offset from a beam axis locks the node's
    rotation in stick and frees it in slip, so full Newton corrections alternate).

    ``stall`` (static, 0: off): give up, with status STALLED, once ``stall`` iterations
    have passed without the residual halving (below half the last residual that did).
    Newton on a contact event that the step is too long for cycles between contact
    states or creeps at |R|/F ~ 1e-2..1e-5 until the iteration limit; stopping early
    lets the driver cut the step sooner. Off, ``max_iter`` is the only limit.
    """

    def res_only(q):
        return residual(q)[0]

    R0, F0 = residual(q0)

    # The stalled-iterate test must not accept a run-away iterate, whose corrections are
    # also small relative to |q| (full Newton steps on arctan(q - 3) reach |q| ~ 1e292 and
    # were reported converged): it only counts within 1e6 times the problem's scale.
    q_bound = 1e6 * jnp.maximum(jnp.maximum(jnp.linalg.norm(q0), xscale), 1.0)

    def converged(q, R, F, dx):
        qn = jnp.linalg.norm(q)
        still = (dx <= xtol * jnp.maximum(qn, xscale)) & (qn <= q_bound)
        return (jnp.linalg.norm(R) <= rtol * F + atol) | still

    def stalled(it, it_ref):
        return (it - it_ref >= stall) if stall > 0 else jnp.asarray(False)

    def cond(c):
        q, R, F, it, dx, _, it_ref = c
        finite = jnp.all(jnp.isfinite(R)) & jnp.all(jnp.isfinite(q))
        return (it < max_iter) & ~converged(q, R, F, dx) & finite & ~stalled(it, it_ref)

    def body(c):
        q, R, F, it, _, ref, it_ref = c
        _, J = banded.extract(res_only, q, topo)
        dq = -banded.solve(J, R, topo)
        if monotone:
            bound = jnp.linalg.norm(R)
        else:
            bound = growth * jnp.maximum(jnp.linalg.norm(R), rtol * F)

        def ls_cond(ls):
            _, Rn, _, k = ls
            ok = jnp.all(jnp.isfinite(Rn)) & (jnp.linalg.norm(Rn) <= bound)
            return ~ok & (k < max_backtracks)

        def ls_body(ls):
            s, _, _, k = ls
            s = 0.5 * s
            Rn, Fn = residual(q + s * dq)
            return s, Rn, Fn, k + 1

        R1, F1 = residual(q + dq)
        s, Rn, Fn, _ = jax.lax.while_loop(ls_cond, ls_body, (jnp.asarray(1.0), R1, F1, 0))
        if stall > 0:  # static: no bookkeeping in the loop when off
            rn = jnp.linalg.norm(Rn)
            halved = rn <= 0.5 * ref
            ref, it_ref = jnp.where(halved, rn, ref), jnp.where(halved, it + 1, it_ref)
        return q + s * dq, Rn, Fn, it + 1, jnp.linalg.norm(s * dq), ref, it_ref

    zero = jnp.asarray(0)
    init = (q0, R0, F0, zero, jnp.asarray(jnp.inf), jnp.linalg.norm(R0), zero)
    q, R, F, it, dx, _, it_ref = jax.lax.while_loop(cond, body, init)
    finite = jnp.all(jnp.isfinite(R)) & jnp.all(jnp.isfinite(q))
    failed = jnp.where(stalled(it, it_ref), STALLED, MAX_ITERATIONS)
    status = jnp.where(~finite, NONFINITE, jnp.where(converged(q, R, F, dx), SUCCESS, failed))
    return q, it, jnp.linalg.norm(R), F, status
