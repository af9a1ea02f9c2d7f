"""The actuated body length as a prescribed stretch of the rigid link between the two ends.

Step 1 (gravity) holds the length; step 2 starts at ``delay`` (s). The stretch is minus the
shortening (the link's reference length L becomes L - s(t)). Both forms are PyTrees whose
numbers are leaves, so designs with other strokes share one compiled program.
"""

from __future__ import annotations

from typing import Any

import jax.numpy as jnp

from bristlecrawler._pytree import pytree
from bristlecrawler.fe.motion import interp


@pytree()
class DelayedSin2:
    """Stretch ``-s_max sin^2(pi (t - delay) / period)`` for ``delay <= t <= delay + cycles T``,
    0 before and after. s_max in mm, period and delay in s."""

    s_max: Any
    period: Any
    delay: Any
    cycles: Any

    def __call__(self, t):
        tau = jnp.clip(t - self.delay, 0.0, self.cycles * self.period)
        return -self.s_max * jnp.sin(jnp.pi * tau / self.period) ** 2


@pytree()
class SampledStretch:
    """Stretch ``-s(t - delay)`` from samples (times s, shortenings mm), linear between them,
    held at the end values outside."""

    t: Any
    s: Any
    delay: Any

    def __call__(self, t):
        return -interp(t - self.delay, self.t, self.s)
