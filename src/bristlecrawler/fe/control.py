"""The adaptive step rule shared by every time and load stepper of the package."""

from __future__ import annotations

import dataclasses
from typing import Any, NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from bristlecrawler.errors import InputError
from bristlecrawler.fe.options import check_settings, setting
from bristlecrawler.fe.status import STEP_ERROR, STEP_TOO_SMALL, SUCCESS, is_fatal


class Outcome(NamedTuple):
    """What the step rule makes of an attempted step: its ``status`` (STEP_ERROR for a
    converged step the energy check refuses, STEP_TOO_SMALL for a failure that ends the
    run), the ``cause`` (the status before STEP_TOO_SMALL), whether it is accepted
    (``good``), the next step size ``dt`` (s), and whether the run ends (``failed``)."""

    status: Any
    cause: Any
    good: Any
    dt: Any
    failed: Any


@dataclasses.dataclass(frozen=True)
class StepControl:
    """Halve a step that fails; after a step that converged within ``easy_iterations``
    Newton iterations, grow the next one by ``grow`` (up to the stepper's largest step).

    One object, one set of defaults and one rule (:meth:`decide`), used by
    every loop of :class:`fe.Stepper` (host, compiled and batched), the load stepping of
    :func:`fe.solve_static`, the contact verification stepper and the crawler runs
    (``[solver] grow, easy_iterations``). Hashable, so it is part of the drivers'
    caches."""

    grow: float = setting(
        1.5, "factor a step grows by after an easy one, - (1: never grows)", ge=1.0, le=10.0
    )
    easy_iterations: int = setting(
        4,
        "a step that took at most this many Newton iterations is easy: the next one grows",
        ge=0,
        le=1000,
    )

    def __post_init__(self) -> None:
        try:
            check_settings(self)
        except InputError as exc:
            raise InputError(f"step control: {exc}") from None

    def next_dt(self, dt, h, good, easy, dt_max):
        """The next step: ``dt`` (s) grown (within ``dt_max``) after an ``easy`` ``good``
        step, kept after a hard one, and half the attempted ``h`` after a failure. Works on
        Python numbers (host loops) and traced arrays (compiled loops) alike."""
        if isinstance(good, bool) and isinstance(easy, bool):
            if not good:
                return 0.5 * h
            return min(dt * self.grow, dt_max) if easy else dt
        grown = jnp.where(easy, jnp.minimum(dt * self.grow, dt_max), dt)
        return jnp.where(good, grown, 0.5 * h)

    def decide(self, status, iterations, h, dt, dt_min, dt_max, ratio=None) -> Outcome:
        """The rule for a step of ``h`` (s), attempted at step size ``dt``, that ended with
        ``status`` after ``iterations`` Newton iterations; ``ratio``: its energy check's
        error over the bound (None: no check).

        A converged step whose ratio is above 1 (or NaN) is refused (STEP_ERROR). An
        accepted step is easy within ``easy_iterations`` and, with a check, when a step
        ``grow**3`` times as long would still pass it (the error grows about as h^3);
        the next step then grows. A failed step is halved; the run ends when half of it
        is below ``dt_min`` or its status is fatal (:data:`status.FATAL`, which a
        smaller step cannot cure). Works on Python numbers (host loops) and traced
        arrays (compiled loops) alike."""
        args = (status, iterations, h, dt, ratio)
        if any(isinstance(a, jax.Array) for a in args):
            return self._decide(jnp, status, iterations, h, dt, dt_min, dt_max, ratio)
        out = self._decide(np, np.asarray(status), iterations, h, dt, dt_min, dt_max, ratio)
        return Outcome(int(out[0]), int(out[1]), bool(out[2]), float(out[3]), bool(out[4]))

    def _decide(self, xp, status, iterations, h, dt, dt_min, dt_max, ratio) -> Outcome:
        easy = xp.asarray(iterations <= self.easy_iterations)
        if ratio is not None:
            refused = (status == SUCCESS) & ~(ratio <= 1.0)
            status = xp.where(refused, STEP_ERROR, status)
            easy = easy & (ratio * self.grow**3 <= 1.0)
        good = xp.asarray(status == SUCCESS)
        grown = xp.where(easy, xp.minimum(dt * self.grow, dt_max), dt)
        nxt = xp.where(good, grown, 0.5 * h)
        fatal = xp.asarray(is_fatal(status))
        failed = ~good & ((0.5 * h < dt_min) | fatal)
        final = xp.where(failed & ~fatal, STEP_TOO_SMALL, status)
        return Outcome(final, status, good, nxt, failed)


#: The defaults, as a default argument.
DEFAULT_CONTROL = StepControl()


class Attempt(NamedTuple):
    """One try of :func:`march`: the step ``h`` tried, what ``attempt`` returned for it
    (``new`` and its ``info``) and the rule's :class:`Outcome`."""

    h: float
    new: Any
    info: Any
    outcome: Outcome


def march(attempt, state, t, t_end, dt, dt_min, dt_max, control=None, *, time_of=None, more=None):
    """The host loop of every adaptive stepper (time steps of :class:`fe.Stepper`'s host
    loop, load increments of :func:`fe.solve_static`, the contact
    verification's stepper): from ``state`` at ``t`` towards ``t_end``, try a step of
    ``min(dt, t_end - t)``, let :meth:`StepControl.decide` judge it, and go on from the
    new state where it is accepted. The compiled drivers run the same rule in a
    ``lax.while_loop`` of their own.

    ``attempt(state, h) -> (new, info, status, ratio)``: the step's result, its
    :class:`~bristlecrawler.fe.status.StepInfo` (or anything with ``iterations``), its
    status after the caller's own checks (an int) and its energy check's ratio (None:
    none). ``time_of(new)``: the time an accepted ``new`` is at (default ``t + h``).
    ``more()``: whether to go on (default: until ``t_end``). Yields one :class:`Attempt`
    per try and stops after the end, or after a try whose outcome ends the run
    (``outcome.failed``)."""
    control = DEFAULT_CONTROL if control is None else control
    eps = 1e-12 * max(1.0, abs(t_end))
    while t < t_end - eps and (more is None or more()):
        h = min(dt, t_end - t)
        new, info, status, ratio = attempt(state, h)
        out = control.decide(status, int(info.iterations), h, dt, dt_min, dt_max, ratio)
        dt = out.dt
        yield Attempt(h, new, info, out)
        if out.failed:
            return
        if out.good:
            state = new
            t = time_of(new) if time_of is not None else t + h
