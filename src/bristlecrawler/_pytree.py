"""Frozen dataclasses registered as JAX PyTrees, for the FE core, contact and crawler.

Numeric fields are leaves (not static metadata), so one ``jax.jit``-compiled kernel serves
every design of the same topology and ``jax.vmap`` runs over a batch of designs. Fields
named in ``meta`` are static (part of the compiled program; they must be hashable).

Validation may live in ``__post_init__`` and runs only where an object is constructed:
JAX rebuilds an object from its leaves without calling the constructor, because inside
``jit``/``vmap``/``grad`` a leaf may be a tracer (no value to check), ``None`` or a
batching sentinel. A ``__post_init__`` that checks values guards them with
:func:`is_concrete`.
"""

from __future__ import annotations

import dataclasses
import operator
from collections.abc import Callable
from typing import Any, TypeVar

import jax
import numpy as np

import bristlecrawler._x64  # noqa: F401  (float64 leaves from as_float_leaf)

T = TypeVar("T")


def pytree(meta: tuple[str, ...] = ()) -> Callable[[type[T]], type[T]]:
    """Class decorator: frozen dataclass + PyTree with all fields but ``meta`` as leaves."""

    def wrap(cls: type[T]) -> type[T]:
        cls = dataclasses.dataclass(frozen=True)(cls)
        names = [f.name for f in dataclasses.fields(cls)]
        unknown = set(meta) - set(names)
        if unknown:
            raise TypeError(f"{cls.__name__}: meta names no field {sorted(unknown)}")
        data = tuple(n for n in names if n not in meta)
        static = tuple(n for n in names if n in meta)
        keys = tuple(jax.tree_util.GetAttrKey(n) for n in data)

        def flatten_with_keys(obj: Any) -> tuple[tuple[Any, ...], tuple[Any, ...]]:
            leaves = tuple((k, getattr(obj, n)) for k, n in zip(keys, data, strict=True))
            return leaves, tuple(getattr(obj, n) for n in static)

        # attrgetter of several names returns a tuple: the fast path of every jit call.
        get_data = operator.attrgetter(*data) if len(data) > 1 else _one(data)
        get_static = operator.attrgetter(*static) if len(static) > 1 else _one(static)

        def flatten(obj: Any) -> tuple[tuple[Any, ...], tuple[Any, ...]]:
            return get_data(obj), get_static(obj)

        def unflatten(aux: tuple[Any, ...], leaves: Any) -> Any:
            obj = object.__new__(cls)
            for n, v in zip(data, leaves, strict=True):
                object.__setattr__(obj, n, v)
            for n, v in zip(static, aux, strict=True):
                object.__setattr__(obj, n, v)
            return obj

        jax.tree_util.register_pytree_with_keys(cls, flatten_with_keys, unflatten, flatten)
        return cls

    return wrap


def _one(names: tuple[str, ...]) -> Callable[[Any], tuple[Any, ...]]:
    """A getter of zero or one attribute that returns a tuple, as attrgetter does for more."""
    if not names:
        return lambda obj: ()
    name = names[0]
    return lambda obj: (getattr(obj, name),)


def is_concrete(*values: Any) -> bool:
    """True if no value is a JAX tracer (so it can be checked with numpy)."""
    return not any(isinstance(v, jax.core.Tracer) for v in values)


def as_float_leaf(obj: Any, name: str) -> np.ndarray | Any:
    """Store field ``name`` of a frozen dataclass as a float64 array (tracers untouched)."""
    value = getattr(obj, name)
    if is_concrete(value):
        value = jax.numpy.asarray(value, dtype=jax.numpy.float64)
        object.__setattr__(obj, name, value)
    return value
