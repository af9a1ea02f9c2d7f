"""Frozen dataclasses registered as JAX PyTrees.

Numeric fields are leaves, so one compiled kernel serves every design of the same topology
and ``jax.vmap`` runs over a batch of designs. Fields named in ``meta`` are static (part of
the compiled program). No validation in ``__post_init__``: JAX rebuilds these objects from
tracers, so checks live at the edge (:mod:`bristlecrawler.fe.structure`).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from typing import Any, TypeVar

import jax

T = TypeVar("T")


def pytree(meta: tuple[str, ...] = ()) -> Callable[[type[T]], type[T]]:
    """Class decorator: frozen dataclass + PyTree with all fields but ``meta`` as leaves."""

    def wrap(cls: type[T]) -> type[T]:
        cls = dataclasses.dataclass(frozen=True)(cls)
        names = [f.name for f in dataclasses.fields(cls)]
        data = [n for n in names if n not in meta]
        jax.tree_util.register_dataclass(cls, data_fields=data, meta_fields=list(meta))
        return cls

    return wrap


def replace(obj: Any, **changes: Any) -> Any:
    """``dataclasses.replace`` (new object, the original is untouched)."""
    return dataclasses.replace(obj, **changes)
