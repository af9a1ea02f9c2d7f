"""The adaptive step rule shared by every time and load stepper of the package."""

from __future__ import annotations

import dataclasses

import jax.numpy as jnp

from bristlecrawler.errors import InputError


@dataclasses.dataclass(frozen=True)
class StepControl:
    """Halve a step that fails; after a step that converged within ``easy_iterations``
    Newton iterations, grow the next one by ``grow`` (up to the stepper's largest step).

    One object, one set of defaults, used by :func:`fe.integrate`, both adaptive drivers
    (:func:`fe.make_driver`, :func:`fe.make_host_driver`), the contact verification
    stepper and the crawler runs (``[solver] grow, easy_iterations``). Hashable, so it is
    part of the drivers' caches."""

    grow: float = 1.5
    easy_iterations: int = 4

    def __post_init__(self) -> None:
        if not self.grow >= 1.0:
            raise InputError(f"step control: grow must be >= 1, got {self.grow}")
        if not (isinstance(self.easy_iterations, int) and self.easy_iterations >= 0):
            raise InputError(
                f"step control: easy_iterations must be a whole number >= 0, got "
                f"{self.easy_iterations!r}"
            )

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


#: The defaults, as a default argument.
DEFAULT_CONTROL = StepControl()
