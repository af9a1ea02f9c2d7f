"""How an options object declares its settings: one name (the scenario file's key), one
default, one meaning with its unit and one valid range per setting, read by the object's
own check and by the tables built from it (a scenario's sections, a command's options);
and the names settings had before, still accepted with a DeprecationWarning.

A base layer (standard library only), so that every layer declares its settings the same
way: the FE core's option objects, the crawler's spec, the reduced model's run, the drag
test and the experiment commands' options.
"""

from __future__ import annotations

import dataclasses
import functools
import math
import numbers
import typing
import warnings
from typing import Any, Literal

from bristlecrawler.errors import InputError

#: Largest length anywhere in a design or a run, mm (10 m): the FE model's coordinates
#: stay far from round-off trouble, and any real crawler fits.
MAX_LENGTH = 1e4

#: The default of a setting that has none: the table must give it.
REQUIRED: Any = dataclasses.MISSING


def setting(
    default: Any,
    doc: str,
    *,
    ge: float | None = None,
    gt: float | None = None,
    le: float | None = None,
    lt: float | None = None,
    inf: bool = False,
    none: bool = False,
    structural: bool = False,
) -> Any:
    """A dataclass field with its meaning (``doc``, ending in ``, unit``) and its valid
    range (``ge``/``gt`` below, ``le``/``lt`` above; ``inf``: infinity allowed, meaning
    off; ``none``: None allowed, meaning the documented fallback). Words (a ``Literal``
    annotation) need no range. ``structural``: the setting shapes the compiled programs,
    so designs that differ in it cannot share one (see :func:`structural_settings`).
    ``default`` :data:`REQUIRED`: no default."""
    bounds = {k: v for k, v in (("ge", ge), ("gt", gt), ("le", le), ("lt", lt)) if v is not None}
    meta = {"doc": doc, "bounds": bounds, "inf": inf, "none": none, "structural": structural}
    return dataclasses.field(default=default, metadata=meta)


def setting_of(
    owner: type,
    name: str,
    *,
    default: Any = REQUIRED,
    why: str = "",
    doc: str | None = None,
    structural: bool | None = None,
    **bounds: float,
) -> Any:
    """The setting ``name`` of the options class ``owner`` declared again for another
    options object that hands it on (the crawler's ``[solver]`` table to
    :class:`NewtonOptions`): the same setting, with its meaning reworded (``doc``), its
    range narrowed (``bounds``: ``ge``, ``gt``, ``le``, ``lt``), and a default of its own
    only with the reason (``why``), which :func:`own_defaults` lists."""
    base = next(f for f in dataclasses.fields(owner) if f.name == name)
    meta = dict(base.metadata)
    inf = bounds.pop("inf", None)
    meta["bounds"] = {**meta["bounds"], **bounds}
    if inf is not None:
        meta["inf"] = bool(inf)
    if doc is not None:
        meta["doc"] = doc
    if structural is not None:
        meta["structural"] = structural
    value = base.default if default is REQUIRED else default
    if value != base.default:
        if not why:
            raise TypeError(f"{owner.__name__}.{name}: a default of its own needs its reason")
        meta["own_default"] = (base.default, why)
    return dataclasses.field(default=value, metadata=meta)


def own_defaults(cls: type) -> dict[str, tuple[Any, Any, str]]:
    """name -> (this default, the default of the options class it hands the setting on
    to, why they differ), for each setting of ``cls`` declared with a default of its own
    (:func:`setting_of`)."""
    return {
        f.name: (f.default, *f.metadata["own_default"])
        for f in settings_of(cls)
        if "own_default" in f.metadata
    }


def settings_of(cls: type) -> list[dataclasses.Field]:
    """The fields of a dataclass that are declared with :func:`setting`."""
    return [f for f in dataclasses.fields(cls) if "bounds" in f.metadata]


def structural_settings(cls: type, prefix: str = "") -> tuple[str, ...]:
    """The names (with ``prefix``) of the settings of ``cls`` declared structural."""
    return tuple(f"{prefix}{f.name}" for f in settings_of(cls) if f.metadata["structural"])


def _words(annotation: Any) -> tuple | None:
    """The allowed words of a ``Literal`` annotation (or ``Literal | None``), else None."""
    if typing.get_origin(annotation) is Literal:
        return typing.get_args(annotation)
    for arg in typing.get_args(annotation):
        if typing.get_origin(arg) is Literal:
            return typing.get_args(arg)
    return None


def _bound_error(name: str, v: float, b: dict, inf: bool) -> str | None:
    ops = {"ge": (">=", v >= b.get("ge", 0)), "gt": (">", v > b.get("gt", 0))}
    ops |= {"le": ("<=", v <= b.get("le", 0)), "lt": ("<", v < b.get("lt", 0))}
    for key, (op, ok) in ops.items():
        if key in b and not ok and not (key in ("le", "lt") and math.isinf(v) and inf):
            return f"{name} must be {op} {b[key]:g}, got {v:g}"
    return None


def check_settings(obj: Any, prefix: str = "") -> None:
    """InputError naming the first setting of ``obj`` outside its declared range (whole
    numbers for ``int`` fields, text for ``str`` ones; NaN never; infinity only where
    declared; None only where declared; one of the words of a ``Literal`` field)."""
    hints = typing.get_type_hints(type(obj))
    for f in settings_of(type(obj)):
        v, name = getattr(obj, f.name), f"{prefix}{f.name}"
        words = _words(hints[f.name])
        if v is None and f.metadata["none"]:
            continue
        if words is not None:
            if v not in words:
                raise InputError(f"{name} must be one of {', '.join(map(str, words))}, got {v!r}")
            continue
        if hints[f.name] is bool or isinstance(f.default, bool):
            continue
        if _is_str(hints[f.name]):
            if not isinstance(v, str):
                raise InputError(f"{name} must be a text, got {v!r}")
            continue
        if _is_int(hints[f.name]) and not isinstance(v, numbers.Integral):
            raise InputError(f"{name} must be a whole number, got {v!r}")
        if not isinstance(v, numbers.Real) or isinstance(v, bool) or math.isnan(v):
            raise InputError(f"{name} must be a number, got {v!r}")
        if math.isinf(v) and not f.metadata["inf"]:
            raise InputError(f"{name} must be finite, got {v}")
        message = _bound_error(name, v, f.metadata["bounds"], f.metadata["inf"])
        if message:
            raise InputError(message)


class Settings:
    """Base of an options dataclass whose fields are declared with :func:`setting`: its
    ``check`` is the declared ranges (:func:`check_settings`) and then its ``rules``, the
    rules between settings. A scenario table built from the class checks the ranges
    itself and then runs ``rules`` alone, so each rule runs once."""

    def check(self, prefix: str = "") -> None:
        """InputError naming the first setting out of its range or breaking a rule
        (settings named with ``prefix``)."""
        check_settings(self, prefix)
        self.rules(prefix)

    def rules(self, prefix: str = "") -> None:
        """InputError naming the settings that break a rule between them (none here)."""


def _is_int(annotation: Any) -> bool:
    return annotation is int or int in typing.get_args(annotation)


def _is_str(annotation: Any) -> bool:
    return annotation is str or str in typing.get_args(annotation)


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
