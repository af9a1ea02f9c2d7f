"""Which fields of a :class:`CrawlerSpec` shape the compiled programs (structure) and which
are values in their parameters.

Designs that differ only in values run in one compiled program, side by side
(:func:`crawler.run_batch`): the bristles' inclination (their reference coordinates),
sections and materials, the friction coefficient, the body's mass, the substrate's
dimensions where the corner contact is off, the damping ratio, the step bounds, the
stroke (its amplitude, period, cycles, delays and gait; a sampled history's values). The
structure is the number of bristles and their elements, the contact options, the form of
the stroke (sin^2, or a sampled history and its number of samples), the solver's settings
and the substrate's kind.
"""

from __future__ import annotations

import dataclasses
import typing

import numpy as np

from bristlecrawler.crawler.spec import CrawlerSpec
from bristlecrawler.errors import InputError
from bristlecrawler.fe.options import structural_settings


def _sections() -> dict[str, type]:
    """The spec's option groups by the name their keys start with (``bristle.``)."""
    hints = typing.get_type_hints(CrawlerSpec)
    out = {"bristle": typing.get_args(hints["bristles"])[0]}
    out |= {name: kind for name, kind in hints.items() if dataclasses.is_dataclass(kind)}
    return out


#: Spec keys that are part of the compiled programs: the settings declared structural
#: (:func:`fe.options.setting`), and the forms that are not one setting (how many
#: bristles, which substrate kind, which form of stroke).
STRUCTURE_KEYS = (
    "bristle count",
    "substrate kind",
    "stroke form",
    *(key for name, cls in _sections().items() for key in structural_settings(cls, f"{name}.")),
)


def _plain(v):
    if hasattr(v, "shape"):
        return np.asarray(v).tolist()
    if isinstance(v, tuple | list):
        return tuple(_plain(x) for x in v)
    return v


def _stroke_form(a) -> str:
    if a.history is None:
        return "sin^2"
    return f"sampled history of {len(a.history[0])} samples"


def spec_fields(spec: CrawlerSpec) -> dict[str, object]:
    """The spec as flat ``group.field`` keys; a bristle field is one value when every
    bristle has it, else the tuple of the bristles' values."""
    out: dict[str, object] = {
        "bristle count": len(spec.bristles),
        "substrate kind": type(spec.substrate).__name__,
        "gravity": spec.gravity,
        "stroke form": _stroke_form(spec.actuation),
    }
    for group in ("body", "contact", "damping", "actuation", "solver"):
        obj = getattr(spec, group)
        for f in dataclasses.fields(obj):
            out[f"{group}.{f.name}"] = _plain(getattr(obj, f.name))
    for f in dataclasses.fields(spec.bristles[0]):
        values = tuple(_plain(getattr(b, f.name)) for b in spec.bristles)
        out[f"bristle.{f.name}"] = values[0] if len(set(map(repr, values))) == 1 else values
    if dataclasses.is_dataclass(spec.substrate):
        for f in dataclasses.fields(spec.substrate):
            out[f"substrate.{f.name}"] = _plain(getattr(spec.substrate, f.name))
    return out


def _structural(key: str) -> bool:
    return any(key == k or (k.endswith(".") and key.startswith(k)) for k in STRUCTURE_KEYS)


def differences(a: CrawlerSpec, b: CrawlerSpec) -> list[tuple[str, object, object]]:
    """(key, value in a, value in b) for every key where two specs differ."""
    fa, fb = spec_fields(a), spec_fields(b)
    return [(k, fa[k], fb.get(k)) for k in fa if repr(fa[k]) != repr(fb.get(k))]


def check_one_structure(specs) -> None:
    """Refuse (:class:`InputError`, one line naming the key) designs whose structure
    differs from the first design's."""
    for i, spec in enumerate(specs[1:], start=1):
        for key, x, y in differences(specs[0], spec):
            if _structural(key):
                raise InputError(
                    f"the designs of a batch must share one structure: {key} differs: "
                    f"{x} vs {y} (designs 0 and {i})"
                )


def structure_key(spec: CrawlerSpec, leave_out: tuple[str, ...] = ()) -> str:
    """A key equal for designs that :func:`check_one_structure` lets batch together
    (``leave_out``: structural keys that the programs in question do not depend on)."""
    f = spec_fields(spec)
    keep = (k for k in f if _structural(k) and k not in leave_out)
    return repr(sorted((k, repr(f[k])) for k in keep))
