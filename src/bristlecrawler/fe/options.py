"""How an options object declares its settings: one name (the scenario file's key), one
default, one meaning with its unit and one valid range per setting, read by the object's
own check and by the scenario schema built from it; and the names settings had before,
still accepted with a DeprecationWarning.
"""

from __future__ import annotations

import dataclasses
import functools
import math
import numbers
import warnings
from typing import Any

from bristlecrawler.errors import InputError


def setting(
    default: Any,
    doc: str,
    *,
    ge: float | None = None,
    gt: float | None = None,
    le: float | None = None,
    inf: bool = False,
) -> Any:
    """A dataclass field with its meaning (``doc``, ending in ``, unit``) and its valid
    range (``ge``/``gt`` below, ``le`` above; ``inf``: infinity allowed, meaning off).
    Words (a ``Literal`` annotation) need no range."""
    bounds = {k: v for k, v in (("ge", ge), ("gt", gt), ("le", le)) if v is not None}
    return dataclasses.field(default=default, metadata={"doc": doc, "bounds": bounds, "inf": inf})


def check_settings(obj: Any, prefix: str = "") -> None:
    """InputError naming the first setting of ``obj`` outside its declared range (whole
    numbers for ``int`` fields; NaN never; infinity only where declared)."""
    for f in dataclasses.fields(obj):
        if "bounds" not in f.metadata:
            continue
        v, name = getattr(obj, f.name), f"{prefix}{f.name}"
        if isinstance(f.default, bool) or isinstance(v, str):
            continue
        if isinstance(f.default, int) and not isinstance(v, numbers.Integral):
            raise InputError(f"{name} must be a whole number, got {v!r}")
        if not isinstance(v, numbers.Real) or math.isnan(v):
            raise InputError(f"{name} must be a number, got {v!r}")
        if math.isinf(v) and not f.metadata["inf"]:
            raise InputError(f"{name} must be finite, got {v}")
        b = f.metadata["bounds"]
        if "ge" in b and not v >= b["ge"]:
            raise InputError(f"{name} must be >= {b['ge']:g}, got {v:g}")
        if "gt" in b and not v > b["gt"]:
            raise InputError(f"{name} must be > {b['gt']:g}, got {v:g}")
        if "le" in b and not v <= b["le"] and not (math.isinf(v) and f.metadata["inf"]):
            raise InputError(f"{name} must be <= {b['le']:g}, got {v:g}")


def _warn(cls_name: str, old: str, new: str) -> None:
    warnings.warn(f"{cls_name}.{old} is deprecated: use {new}", DeprecationWarning, stacklevel=3)


def renamed(**old_to_new: str):
    """Class decorator for a frozen dataclass: accept each old keyword in ``old_to_new``
    as its new one, with a DeprecationWarning, and read the old attribute as the new one.
    Given both, the old one wins: ``dataclasses.replace(obj, old=value)`` passes the new
    name with the object's current value beside it."""

    def wrap(cls):
        init = cls.__init__

        @functools.wraps(init)
        def __init__(self, *args, **kw):
            for old, new in old_to_new.items():
                if old in kw:
                    _warn(cls.__name__, old, new)
                    kw[new] = kw.pop(old)
            init(self, *args, **kw)

        cls.__init__ = __init__
        cls.renamed_from = dict(old_to_new)
        for old, new in old_to_new.items():

            def get(self, old=old, new=new):
                _warn(type(self).__name__, old, new)
                return getattr(self, new)

            setattr(cls, old, property(get))
        return cls

    return wrap


def compose(owner: str, parts: dict[str, Any], settings: dict[str, Any]) -> dict[str, Any]:
    """The option objects ``parts`` (name -> object) with ``settings`` (keyword -> value)
    given to the part that has a setting of that name (or had it, see :func:`renamed`):
    how a composed options object takes its parts' settings as plain keywords."""
    out = dict(parts)
    for key, value in settings.items():
        for name, part in out.items():
            names = {f.name for f in dataclasses.fields(part)} | set(
                getattr(type(part), "renamed_from", {})
            )
            if key in names:
                out[name] = dataclasses.replace(part, **{key: value})
                break
        else:
            raise TypeError(f"{owner} got an unexpected keyword argument {key!r}")
    return out
