"""Prescribed functions of time: actuator strokes, load amplitudes, support motions.

Each motion is a small PyTree whose parameters are leaves, so a batch of structures can
differ in stroke amplitude or period under ``jax.vmap``. ``motion(t)`` takes and returns a
float64 scalar. Units are those of the quantity it prescribes (mm for displacements,
rad for rotations, 1 for load amplitudes); ``t`` is in s.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import jax
import jax.numpy as jnp
import numpy as np

from bristlecrawler._pytree import pytree


@pytree()
class Constant:
    """``value`` at all times."""

    value: float = 0.0

    def __call__(self, t):
        return jnp.asarray(self.value, dtype=jnp.float64) + 0.0 * t


@pytree()
class Sin2:
    """Paper stroke s(t) = s~ sin^2(pi t / T) (Section 3): ``amplitude`` s~, ``period`` T (s)."""

    amplitude: float
    period: float

    def __call__(self, t):
        return self.amplitude * jnp.sin(jnp.pi * t / self.period) ** 2


@pytree()
class Ramp:
    """Linear rise from 0 at t = 0 to ``value`` at t = ``duration`` (s), then constant."""

    value: float
    duration: float

    def __call__(self, t):
        return self.value * jnp.clip(t / self.duration, 0.0, 1.0)


@pytree()
class SmoothRamp:
    """From 0 at t = 0 to ``value`` at t = ``duration`` (s), then constant, with a
    trapezoidal velocity profile: the velocity rises linearly over the first ``blend`` s,
    stays constant, and falls linearly to zero over the last ``blend`` s
    (0 < ``blend`` <= ``duration`` / 2; ``blend = duration / 2`` is an S-curve).

    Unlike :class:`Ramp` the velocity is continuous, so a structure at rest is not given an
    impulse at t = 0 (a velocity jump of a prescribed DOF is an infinite acceleration, which
    an implicit integrator turns into a one-step spike and high-frequency ringing).
    """

    value: float
    duration: float
    blend: float

    def __call__(self, t):
        T, b = self.duration, self.blend
        v = self.value / (T - b)  # cruise velocity
        tau = jnp.clip(t, 0.0, T)
        start = 0.5 * v / b * tau**2
        cruise = v * (tau - 0.5 * b)
        stop = self.value - 0.5 * v / b * (T - tau) ** 2
        return jnp.where(tau < b, start, jnp.where(tau > T - b, stop, cruise))


@pytree()
class Sine:
    """``amplitude`` sin(``omega`` t), omega in rad/s."""

    amplitude: float
    omega: float

    def __call__(self, t):
        return self.amplitude * jnp.sin(self.omega * t)


def interp(x, xp, fp):
    """``jnp.interp(x, xp, fp)`` for increasing ``xp`` (the same arithmetic, so the same
    bits), held at the end values outside ``xp``, with the interval found by comparing
    ``x`` with every ``xp`` at once rather than by ``searchsorted``'s bisection: that is
    a loop of log2(n) passes in a compiled program, each a round of small kernels, where
    one vectorised comparison of a few tens of knots costs one."""
    n = xp.shape[0]
    i = jnp.clip(jnp.searchsorted(xp, x, side="right", method="compare_all"), 1, n - 1)
    df = fp[i] - fp[i - 1]
    dx = xp[i] - xp[i - 1]
    delta = x - xp[i - 1]
    dx0 = jnp.abs(dx) <= np.spacing(np.finfo(xp.dtype).eps)
    f = jnp.where(dx0, fp[i - 1], fp[i - 1] + (delta / jnp.where(dx0, 1, dx)) * df)
    f = jnp.where(x < xp[0], fp[0], f)
    return jnp.where(x > xp[-1], fp[-1], f)


@pytree()
class Piecewise:
    """Linear between the knots (``times`` s, increasing; ``values``), held at the end
    values outside them (a carriage's path, a sampled stroke)."""

    times: Any
    values: Any

    def __call__(self, t):
        return interp(t, self.times, self.values)


@pytree(meta=("fn",))
class TimeFunction:
    """Any JAX-traceable ``fn(t)``; the function is static (not batched by ``vmap``)."""

    fn: Callable

    def __call__(self, t):
        return jnp.asarray(self.fn(t), dtype=jnp.float64)


def _numeric(x) -> bool:
    return isinstance(x, int | float | np.ndarray | jax.Array | np.number)


def as_motion(value) -> object:
    """A number becomes :class:`Constant`; a motion is returned as is; a callable is wrapped.

    A callable registered as a PyTree whose leaves are all numbers (such as the crawler's
    strokes) is a motion already: its numbers stay parameters of the compiled programs,
    so motions that differ only in them share one program. Wrapping it in
    :class:`TimeFunction` would compile them in."""
    if isinstance(value, Constant | Sin2 | Ramp | SmoothRamp | Sine | Piecewise | TimeFunction):
        return value
    if callable(value):
        leaves = jax.tree_util.tree_leaves(value)
        if leaves and all(_numeric(x) for x in leaves):
            return value
        return TimeFunction(value)
    return Constant(float(value))
