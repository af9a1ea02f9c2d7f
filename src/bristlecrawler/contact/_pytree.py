"""Frozen dataclasses that are JAX PyTrees whose every field is a leaf.

Parameters are leaves (not static metadata) so that one ``jax.jit``-compiled kernel serves
every design of the same shape and ``jax.vmap`` can run over a batch of designs.
Validation lives in ``__post_init__`` and only runs on concrete values: when JAX rebuilds
an object from traced leaves (inside ``jit``/``vmap``/``grad``) the constructor is bypassed,
because a tracer has no value to check.
"""

from __future__ import annotations

import dataclasses
from typing import Any

import jax
import numpy as np


def is_concrete(*values: Any) -> bool:
    """True if no value is a JAX tracer (so it can be checked with numpy)."""
    return not any(isinstance(v, jax.core.Tracer) for v in values)


def pytree_dataclass(cls: type) -> type:
    """Make ``cls`` a frozen dataclass registered as a PyTree with all fields as leaves."""
    cls = dataclasses.dataclass(frozen=True)(cls)
    names = tuple(f.name for f in dataclasses.fields(cls))

    def flatten(obj: Any) -> tuple[tuple[Any, ...], None]:
        return tuple(getattr(obj, n) for n in names), None

    def unflatten(_aux: None, leaves: tuple[Any, ...]) -> Any:
        # Bypass __init__/__post_init__: leaves may be tracers, None or batching sentinels.
        obj = object.__new__(cls)
        for n, v in zip(names, leaves, strict=True):
            object.__setattr__(obj, n, v)
        return obj

    jax.tree_util.register_pytree_node(cls, flatten, unflatten)
    return cls


def as_float_leaf(obj: Any, name: str) -> np.ndarray | Any:
    """Store field ``name`` of a frozen dataclass as a float64 array (tracers untouched)."""
    value = getattr(obj, name)
    if is_concrete(value):
        value = jax.numpy.asarray(value, dtype=jax.numpy.float64)
        object.__setattr__(obj, name, value)
    return value
