"""Newton-Raphson with backtracking line search, jit/vmap friendly (``lax.while_loop``).

Tangent by coloured JVPs of the residual (:func:`banded.extract`), solve by the bordered
block-tridiagonal algorithm. Two line searches:

* growth (the default of :class:`fe.Integrator`): a correction is halved (at most
  ``max_backtracks`` times) only while the trial residual is NaN/inf or larger than
  ``growth`` (1e6) times the current one. For a slender beam it keeps the good full Newton
  steps that monotone merits cut: from the straight cantilever the full step overshoots in
  axial strain by a factor ~1e4 in |R| and the next step removes it; Armijo on |R|^2,
  Crisfield's energy-slope search (Crisfield 1991, Sec. 9.3) and Deuflhard's natural
  monotonicity test needed 30-45 iterations instead of 6-8 for P L^2/EI = 1..10.
* monotone: halve until the residual decreases. It breaks the cycle of a contact point
  that flips between stick and slip from one iterate to the next, which is why the crawler
  scenarios use it (``[solver] line_search``).

Robustness otherwise comes from the adaptive load and time steps.
Converged when |R| <= tolerance F + atol, F the force scale returned by the residual.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any, Literal, NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from bristlecrawler.errors import InputError
from bristlecrawler.fe import banded
from bristlecrawler.fe.options import check_settings, renamed, setting
from bristlecrawler.fe.status import MAX_ITERATIONS, NONFINITE, STALLED, SUCCESS


@renamed(
    rtol="tolerance",
    max_iter="max_iterations",
    stall="stall_iterations",
    freeze="freeze_iterations",
)
@dataclasses.dataclass(frozen=True)
class NewtonOptions:
    """Settings of :func:`newton`, one object for the dynamic step (:class:`Integrator`),
    the static solver (:class:`StaticOptions`) and the crawler's ``[solver]`` table, whose
    keys have the same names. Static: part of the compiled programs, so hashable.

    Attributes:
        tolerance, atol: converged when |R| <= tolerance F + atol (F the residual's force
            scale, N).
        max_iterations: iterations per solve.
        line_search: "growth" (halve only against blow-ups) or "monotone" (halve until the
            residual decreases).
        stall_iterations: give up (status STALLED) once this many iterations pass without
            the residual halving (0: off).
        freeze_iterations: first iterations that keep the contact statuses frozen (0: off);
            < max_iterations.
        max_correction: largest translation (mm) of a correction's first trial (inf: off).
        xtol: converged when the last correction is below xtol max(|q|, size).
        max_backtracks: halvings of one correction.
        growth: the growth search's bound on |R_new| / |R|.

    The names before (``rtol``, ``max_iter``, ``stall``, ``freeze``) still work, with a
    DeprecationWarning.
    """

    tolerance: float = setting(
        1e-9, "Newton tolerance on the relative residual, -", ge=0.0, inf=True
    )
    atol: float = setting(0.0, "absolute residual tolerance, N", inf=True)
    max_iterations: int = setting(12, "Newton iterations per solve", ge=1)
    line_search: Literal["growth", "monotone"] = setting(
        "growth",
        "halve a correction only against blow-ups ('growth') or until the residual "
        "decreases ('monotone')",
    )
    stall_iterations: int = setting(
        0, "iterations without the residual halving before giving up (0: off)", ge=0
    )
    freeze_iterations: int = setting(
        0, "first iterations that keep the contact statuses frozen (0: off)", ge=0
    )
    max_correction: float = setting(
        math.inf,
        "largest translation of a correction's first trial, mm (inf: off)",
        gt=0.0,
        inf=True,
    )
    xtol: float = setting(1e-13, "converged below this relative correction, -", inf=True)
    max_backtracks: int = setting(8, "halvings of one correction")
    growth: float = setting(1e6, "the growth search's bound on |R_new| / |R|, -", inf=True)

    def __post_init__(self) -> None:
        # max_iterations >= 1 is also required by the predictor: iteration 0 must run,
        # since the start's residual comes from its linearisation.
        check_settings(self)
        n = self.max_iterations
        if not self.freeze_iterations < n:
            raise InputError(
                f"freeze_iterations must be below max_iterations = {n}, "
                f"got {self.freeze_iterations!r}"
            )


#: The defaults, as a default argument.
DEFAULT_NEWTON = NewtonOptions()


class _Iterate(NamedTuple):
    """Newton's loop state: iterate, residual, force scale, iteration count, last
    correction's size, the residual and iteration the stall test counts from, and
    whether the contact statuses are still frozen."""

    q: Any
    R: Any
    F: Any
    it: Any
    dx: Any
    ref: Any
    it_ref: Any
    fz: Any


def _line_search(res, q, dq, R, F, s0, pred, o: NewtonOptions, parallel=False):
    """The step length along ``dq`` from ``q`` (residual ``R``, force scale ``F``) and the
    residual and force scale there: the first trial at ``s0`` (taken whole on the
    predictor ``pred``), halved while the residual is not finite or above the bound of
    ``o.line_search`` (see :func:`newton`), at most down to ``2**-o.max_backtracks``.

    ``parallel`` (static): evaluate every trial the search could make at once (one
    vectorised residual of ``max_backtracks + 1`` points) and take the first it would
    accept. The trials are the same numbers (halving is exact in floating point), so the
    result is the sequential search's; the cost is the work of all the trials in one
    pass instead of a loop of as many passes as the search needs. Under ``vmap`` a
    sequential search runs as many trials as the batch's longest search, every time:
    with a third of the paper crawler's corrections backtracking, up to eight halvings,
    a batch of 64 designs or more makes all nine nearly every iteration."""
    if o.line_search == "monotone":
        bound = jnp.linalg.norm(R)
    else:
        bound = o.growth * jnp.maximum(jnp.linalg.norm(R), o.tolerance * F)
    floor = 0.5**o.max_backtracks  # smallest trial, a fraction of the whole correction

    def accepted(Rn):
        return pred | (jnp.all(jnp.isfinite(Rn)) & (jnp.linalg.norm(Rn) <= bound))

    if parallel:
        s = s0 * np.ldexp(1.0, -np.arange(o.max_backtracks + 1))  # exact halvings
        Rs, Fs = jax.vmap(lambda si: res(q + si * dq))(s)
        # The sequential search stops at its first accepted trial or at the floor.
        stop = jax.vmap(accepted)(Rs) | (s <= floor)
        j = jnp.argmax(stop)
        return s[j], Rs[j], Fs[j]

    def ls_cond(ls):
        s, Rn, _, k = ls
        return (k < 0) | (~accepted(Rn) & (s > floor))

    def ls_body(ls):
        s, _, _, k = ls
        s = 0.5 * s
        Rn, Fn = res(q + s * dq)
        return s, Rn, Fn, k + 1

    # k = -1: the first trial is made in the loop too (one residual in the program).
    s, Rn, Fn, _ = jax.lax.while_loop(ls_cond, ls_body, (2.0 * s0, R, F, -1))
    return s, Rn, Fn


def newton(residual, q0, topo, options: NewtonOptions, *, xscale=0.0, predict=None, parallel=False):
    """Solve residual(q)[0] = 0 from ``q0`` with ``options`` (:class:`NewtonOptions`; the
    names below are its fields). Returns (q, iterations, |R|, F, status).

    Also converged when the last correction is below ``xtol`` max(|q|, ``xscale``) (xscale:
    size of the structure, mm): the iterate has stopped moving at round-off. The residual
    has a floor of about |K| eps |X| (stiffness times the float64 spacing of the node
    coordinates), which for a small load on a stiff member (the paper's bristle under
    1e-4 N) is far above tolerance F. The achieved |R|/F is reported either way.

    Each correction is halved (up to ``max_backtracks`` times) while the new residual is
    not finite or exceeds ``growth`` times the current one; with the ``monotone`` line
    search while it does not decrease at all. The monotone search
    breaks the cycle of a contact point that flips between stick and slip from one
    iterate to the next (a friction force offset from a beam axis locks the node's
    rotation in stick and frees it in slip, so full Newton corrections alternate).

    ``max_correction`` (mm; inf: off): the first trial of each correction after the
    predictor is scaled down so that no translation among the unknowns (the reduced
    unknowns of x and y; nodes tied to them by rigid links are not counted) moves by
    more than ``max_correction``; the halvings, if the trial fails, start from there and stop
    at the same floor, ``2**-max_backtracks`` of the whole correction. A fixed cap (a
    trust region of constant radius): after the predictor, Newton moves by at most
    ``max_correction`` per iteration, so an attempt cannot travel further than
    ``max_iterations`` times it. A contact residual is curved on the scale of its penalty
    (microns): a correction that moved a bristle tip by millimetres, through the substrate, raised
    |R| a thousandfold and took all eight halvings to find that even 1/256 of it does
    not decrease |R|; the cap reaches that scale in a few trials.

    ``stall_iterations`` (0: off): give up, with status STALLED, once that many iterations
    have passed without the residual halving (below half the last residual that did).
    Newton on a contact event that the step is too long for cycles between contact
    states or creeps at |R|/F ~ 1e-2..1e-5 until the iteration limit; stopping early
    lets the driver cut the step sooner. Off, ``max_iterations`` is the only limit.

    ``predict = (t0, t1, dt)`` (a time step, ``dt = t1 - t0``): ``residual`` takes
    ``(q, tc)``, the time of the prescribed motions, and the equation solved is
    ``residual(q, t1)[0] = 0``. Iteration 0 is then the tangent (Euler) predictor from
    ``q0``, a state at ``t0``: ``J(q0, t0) dq = -(R(q0, t0) + dR/dtc dt)``, taken whole
    (no line search; no correction where it is not finite) and counted as an iteration.
    It runs in the same loop body as the corrections, so the compiled program holds one
    linearised residual, not two.

    ``freeze_iterations`` (0: off): ``residual`` also takes a bool ``freeze`` (after ``tc``
    when there is one). Newton starts with it True: a contact residual then keeps each
    closed point in the stick or slip status it was committed with (an active-set
    start). It turns False for good once that frozen problem has converged or
    ``freeze_iterations`` iterations have passed; the iterate is then evaluated again with it
    False, and only such iterates can converge. A point whose status flips near the
    step's solution makes full Newton cycle between the branches (the stick band is far
    narrower than a correction); with the statuses frozen the first iterations solve a
    smooth problem, and the free ones start next to the solution when the statuses hold.

    ``parallel`` (static): the line search makes all its trials at once, with the same
    result (:func:`_line_search`).
    """
    parts = newton_parts(
        residual, q0, topo, options, xscale=xscale, predict=predict, parallel=parallel
    )
    return parts.result(jax.lax.while_loop(parts.cond, parts.body, parts.init))


class NewtonParts(NamedTuple):
    """:func:`newton` as the parts of its loop: ``init`` (the first :class:`_Iterate`),
    ``cond(c)`` (iterate again?), ``body(c)`` (one iteration) and ``result(c) -> (q,
    iterations, |R|, F, status)``. A loop that interleaves Newton with other work (one
    iteration per design of a batch, each at its own point of its own solve) runs them
    itself; :func:`newton` is ``result(while_loop(cond, body, init))``."""

    init: Any
    cond: Any
    body: Any
    result: Any


class _Tests(NamedTuple):
    converged: Any
    stalled: Any
    done: Any


def _tests(q0, xscale, o: NewtonOptions) -> _Tests:
    """Newton's stopping tests (see :func:`newton`)."""
    # The stalled-iterate test must not accept a run-away iterate, whose corrections are
    # also small relative to |q| (full Newton steps on arctan(q - 3) reach |q| ~ 1e292 and
    # were reported converged): it only counts within 1e6 times the problem's scale.
    q_bound = 1e6 * jnp.maximum(jnp.maximum(jnp.linalg.norm(q0), xscale), 1.0)

    def converged(q, R, F, dx):
        qn = jnp.linalg.norm(q)
        still = (dx <= o.xtol * jnp.maximum(qn, xscale)) & (qn <= q_bound)
        return (jnp.linalg.norm(R) <= o.tolerance * F + o.atol) | still

    def stalled(it, it_ref):
        return (it - it_ref >= o.stall_iterations) if o.stall_iterations > 0 else jnp.asarray(False)

    def done(q, R, F, dx, fz):
        return converged(q, R, F, dx) & ~fz

    return _Tests(converged, stalled, done)


def newton_parts(
    residual, q0, topo, options: NewtonOptions, *, xscale=0.0, predict=None, parallel=False
):
    """The parts of :func:`newton`'s loop (:class:`NewtonParts`), same arguments;
    ``parallel`` (static): the line search evaluates all its trials at once (the same
    result, see :func:`_line_search`), the form for a batch under ``vmap``."""
    o = options
    if predict is None:
        tc0 = tc1 = dt = jnp.zeros(())
    else:
        tc0, tc1, dt = predict

    def res_t(q, tc, fz):
        if predict is None:
            return residual(q) if o.freeze_iterations == 0 else residual(q, freeze=fz)
        return residual(q, tc) if o.freeze_iterations == 0 else residual(q, tc, fz)

    def first(it):
        return (it == 0) if predict is not None else jnp.asarray(False)

    if predict is None:
        R0, F0 = res_t(q0, tc0, jnp.asarray(o.freeze_iterations > 0))
    else:
        # Iteration 0 (the predictor) always runs and takes the residual at q0 from its own
        # linearisation: no separate evaluation (one residual less per step).
        R0 = jnp.zeros_like(q0)
        F0 = jnp.ones((), q0.dtype)
    translation = None
    if math.isfinite(o.max_correction):
        translation = jnp.asarray(np.asarray(topo.arrays()["red"])[:, 1] < 2)
    tests = _tests(q0, xscale, o)

    def cond(c):
        q, R, F, it, dx, _, it_ref, fz = c
        finite = jnp.all(jnp.isfinite(R)) & jnp.all(jnp.isfinite(q))
        solve = ~tests.done(q, R, F, dx, fz) & finite & ~tests.stalled(it, it_ref)
        return (it < o.max_iterations) & (first(it) | solve)

    def body(c):
        q, R, F, it, _, ref, it_ref, fz = c
        pred = first(it)
        if predict is None:
            _, J = banded.extract(lambda q: res_t(q, tc1, fz)[0], q, topo)
            dq = -banded.solve(J, R, topo)
        else:
            tc = jnp.where(pred, tc0, tc1)
            y, J, Rt = banded.extract(lambda q, tc: res_t(q, tc, fz)[0], q, topo, tc, dt)
            R = jnp.where(pred, y + Rt, R)
            dq = -banded.solve(J, R, topo)
            dq = jnp.where(pred & ~jnp.all(jnp.isfinite(dq)), 0.0, dq)
        s0 = jnp.asarray(1.0)
        if translation is not None:  # static
            move = jnp.max(jnp.where(translation, jnp.abs(dq), 0.0), initial=0.0)
            s0 = jnp.where(pred | (move <= o.max_correction), 1.0, o.max_correction / move)
        s, Rn, Fn = _line_search(lambda x: res_t(x, tc1, fz), q, dq, R, F, s0, pred, o, parallel)
        rn = jnp.linalg.norm(Rn)
        if o.stall_iterations > 0:  # static: no bookkeeping in the loop when off
            halved = rn <= 0.5 * ref
            ref, it_ref = jnp.where(halved, rn, ref), jnp.where(halved, it + 1, it_ref)
        # After the predictor: the corrections start afresh (no stalled-iterate test on
        # the predictor's move; the stall count starts at its residual).
        dx = jnp.where(pred, jnp.inf, jnp.linalg.norm(s * dq))
        ref, it_ref = jnp.where(pred, rn, ref), jnp.where(pred, it + 1, it_ref)
        nxt = _Iterate(q + s * dq, Rn, Fn, it + 1, dx, ref, it_ref, fz)
        if o.freeze_iterations > 0:  # static
            nxt = _unfreeze(nxt, pred, lambda q: res_t(q, tc1, jnp.asarray(False)), tests, o)
        return nxt

    def result(c):
        q, R, F, it, dx, _, it_ref, fz = c
        finite = jnp.all(jnp.isfinite(R)) & jnp.all(jnp.isfinite(q))
        failed = jnp.where(tests.stalled(it, it_ref), STALLED, MAX_ITERATIONS)
        done = tests.done(q, R, F, dx, fz)
        status = jnp.where(~finite, NONFINITE, jnp.where(done, SUCCESS, failed))
        return q, it, jnp.linalg.norm(R), F, status

    zero = jnp.asarray(0)
    fz0 = jnp.asarray(o.freeze_iterations > 0)
    init = _Iterate(q0, R0, F0, zero, jnp.asarray(jnp.inf), jnp.linalg.norm(R0), zero, fz0)
    return NewtonParts(init, cond, body, result)


def _unfreeze(c: _Iterate, pred, free_residual, tests: _Tests, o: NewtonOptions) -> _Iterate:
    """Unfreeze the contact statuses once the frozen problem is solved (not on the
    predictor's move) or after ``o.freeze_iterations`` iterations, and evaluate the iterate with the
    free law (``free_residual``); the free residual starts afresh: no stalled-iterate
    test on this move."""
    q, Rn, Fn, it, dx, ref, it_ref, fz = c
    solved = ~pred & tests.converged(q, Rn, Fn, dx)
    unfreeze = fz & (solved | (it >= o.freeze_iterations))
    Rn, Fn = jax.lax.cond(unfreeze, lambda _: free_residual(q), lambda _: (Rn, Fn), None)
    dx = jnp.where(unfreeze, jnp.inf, dx)
    ref = jnp.where(unfreeze, jnp.linalg.norm(Rn), ref)
    it_ref = jnp.where(unfreeze, it, it_ref)
    return _Iterate(q, Rn, Fn, it, dx, ref, it_ref, fz & ~unfreeze)
