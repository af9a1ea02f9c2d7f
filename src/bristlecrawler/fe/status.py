"""Solver outcomes as values: a status code, counters and a message (diffrax/equinox style).

Kernels never raise inside ``jit``; they return :class:`StepInfo`. Drivers turn a failure
into a message saying where (time, load factor, step), which failure and the residual, and
raise :class:`~bristlecrawler.errors.SolverError` only when called with ``throw=True``.
"""

from __future__ import annotations

import enum

import numpy as np

from bristlecrawler._pytree import pytree
from bristlecrawler.errors import SolverError


class Status(enum.IntEnum):
    """Outcome of a solver step (a value inside compiled programs, so an integer)."""

    SUCCESS = 0
    MAX_ITERATIONS = 1
    NONFINITE = 2
    STEP_TOO_SMALL = 3
    SINGULAR = 4
    ROTATION_LIMIT = 5
    PENETRATION = 6
    STEP_ERROR = 7
    CONTACT_OVERFLOW = 8
    STALLED = 9
    UNSUPPORTED_DAMPING = 10


# The members as module names, for the kernels and drivers.
SUCCESS = Status.SUCCESS
MAX_ITERATIONS = Status.MAX_ITERATIONS
NONFINITE = Status.NONFINITE
STEP_TOO_SMALL = Status.STEP_TOO_SMALL
SINGULAR = Status.SINGULAR
ROTATION_LIMIT = Status.ROTATION_LIMIT
PENETRATION = Status.PENETRATION
STEP_ERROR = Status.STEP_ERROR
CONTACT_OVERFLOW = Status.CONTACT_OVERFLOW
STALLED = Status.STALLED
UNSUPPORTED_DAMPING = Status.UNSUPPORTED_DAMPING

#: Failures a smaller step cannot cure: the drivers stop at once instead of cutting dt.
FATAL = (CONTACT_OVERFLOW, UNSUPPORTED_DAMPING)

_TEXT = {
    SUCCESS: "converged",
    MAX_ITERATIONS: "Newton did not converge within the iteration limit",
    NONFINITE: "residual or solution became NaN/inf (singular tangent or diverging iterate)",
    STEP_TOO_SMALL: "step cut below its minimum",
    SINGULAR: "tangent is singular",
    ROTATION_LIMIT: "increment rotated a node by more than the allowed rotation increment",
    PENETRATION: "converged with a contact penetration beyond the allowed depth",
    STEP_ERROR: "converged, but the step's error estimate is above its tolerance",
    CONTACT_OVERFLOW: (
        "converged with more contact points reaching below the substrate's top than the "
        "contact broad phase evaluates (raise the contact term's 'active' count; a smaller "
        "step does not help)"
    ),
    STALLED: "Newton stalled: the residual stopped halving (stall_iterations)",
    UNSUPPORTED_DAMPING: (
        "stiffness-proportional damping (a1 != 0) on a model built without it "
        "(Structure.stiffness_damping(False); a smaller step does not help)"
    ),
}


def is_fatal(status):
    """True where ``status`` (int or array, traced or not) is in :data:`FATAL`."""
    out = status == FATAL[0]
    for code in FATAL[1:]:
        out = out | (status == code)
    return out


@pytree()
class StepInfo:
    """Outcome of one Newton solve (arrays, batched under ``vmap``).

    status: code (SUCCESS, MAX_ITERATIONS, NONFINITE, ...); iterations: Newton iterations;
    residual: |R| of the reduced residual (N, N mm mixed); rel_residual: |R| / force scale;
    t: time reached (s); dt: step (s, 0 for statics); lam: load factor.
    """

    status: object
    iterations: object
    residual: object
    rel_residual: object
    t: object
    dt: object
    lam: object


def describe(code: int) -> str:
    """Text of a status code."""
    return _TEXT.get(int(code), f"unknown status {int(code)}")


def message(info: StepInfo, where: str = "") -> str:
    """One line: 'dynamics step 12 at t = 0.35 s (dt = 1e-3 s): Newton ... (|R|/F = 3e-4)'."""
    status = np.atleast_1d(np.asarray(info.status))
    bad = np.flatnonzero(status != SUCCESS)
    if bad.size == 0:
        return f"{where}: converged" if where else "converged"
    i = int(bad[0])

    def at(x):
        return float(np.atleast_1d(np.asarray(x))[i])

    batch = f" (batch member {i} of {status.size})" if status.size > 1 else ""
    return (
        f"{where}{batch} at t = {at(info.t):.6g} s, dt = {at(info.dt):.3g} s, "
        f"load factor {at(info.lam):.4g}: {describe(status[i])} after "
        f"{int(at(info.iterations))} iterations (|R| = {at(info.residual):.3e}, "
        f"|R|/F = {at(info.rel_residual):.3e})"
    )


def ok(info: StepInfo) -> bool:
    """True if every member of a (possibly batched) info converged."""
    return bool(np.all(np.asarray(info.status) == SUCCESS))


def check(info: StepInfo, where: str = "", throw: bool = True) -> bool:
    """Raise :class:`SolverError` with :func:`message` on failure if ``throw``; else return ok."""
    good = ok(info)
    if not good and throw:
        raise SolverError(message(info, where))
    return good
