"""TOML form of a substrate, validated by pydantic at the edge.

A ``[substrate]`` table names its ``kind`` and the fields of that kind, for example::

    [substrate]
    kind = "grooves"
    width = 1.0      # mm
    depth = 0.25     # mm
    pitch = 2.0      # mm

The friction coefficient is not a property of the shape: it is ``[contact] mu``.

:func:`parse_substrate` turns a table (a mapping) into a config object, whose ``build()``
returns the substrate; every failure is an :class:`~bristlecrawler.errors.InputError` with one
line naming the offending field.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Annotated, Any, Literal

from pydantic import (
    Field,
    TypeAdapter,
    ValidationError,
    field_validator,
)

from bristlecrawler.contact.substrates import Flat, Grooves, Polyline, Sawtooth
from bristlecrawler.errors import InputError
from bristlecrawler.scenario.strict import StrictSection


class _Base(StrictSection):
    """A substrate table (see :class:`StrictSection`)."""


class FlatConfig(_Base):
    """A flat plane."""

    kind: Literal["flat"]
    height: float = Field(0.0, allow_inf_nan=False, description="surface level, mm")

    def build(self) -> Flat:
        return Flat(height=self.height)


class GroovesConfig(_Base):
    """Rectangular grooves (the paper's substrate)."""

    kind: Literal["grooves"]
    width: float = Field(gt=0, allow_inf_nan=False, description="groove width, mm")
    depth: float = Field(gt=0, allow_inf_nan=False, description="groove depth, mm")
    pitch: float = Field(gt=0, allow_inf_nan=False, description="groove spacing, mm")
    phase: float = Field(0.0, allow_inf_nan=False, description="x of a groove's left wall, mm")
    top: float = Field(0.0, allow_inf_nan=False, description="land level, mm")
    fillet_top: float = Field(
        0.0, ge=0, allow_inf_nan=False, description="radius of the convex land corners, mm"
    )
    fillet_bottom: float = Field(
        0.0, ge=0, allow_inf_nan=False, description="radius of the concave bottom corners, mm"
    )

    def build(self) -> Grooves:
        return Grooves(**self.model_dump(exclude={"kind"}))


class SawtoothConfig(_Base):
    """Asymmetric teeth."""

    kind: Literal["sawtooth"]
    pitch: float = Field(gt=0, allow_inf_nan=False, description="tooth spacing, mm")
    height: float = Field(gt=0, allow_inf_nan=False, description="tooth height, mm")
    rise_fraction: float = Field(
        0.8, ge=0, le=1, allow_inf_nan=False, description="fraction of the pitch rising, -"
    )
    phase: float = Field(0.0, allow_inf_nan=False, description="x of a valley, mm")
    base: float = Field(0.0, allow_inf_nan=False, description="valley level, mm")

    def build(self) -> Sawtooth:
        return Sawtooth(**self.model_dump(exclude={"kind"}))


class PolylineConfig(_Base):
    """Periodic polyline over one period."""

    kind: Literal["polyline"]
    points: list[tuple[float, float]] = Field(
        min_length=2, description="[[x, y], ...] over exactly one period, mm"
    )

    @field_validator("points", mode="before")
    @classmethod
    def _pairs(cls, value):
        # TOML gives [[x, y], ...] as lists (a caller may give an array); strict mode
        # takes tuples of Python floats only.
        if hasattr(value, "tolist"):
            value = value.tolist()
        if isinstance(value, list | tuple):
            return [tuple(p) if isinstance(p, list) else p for p in value]
        return value

    def build(self) -> Polyline:
        return Polyline(points=self.points)


SubstrateConfig = Annotated[
    FlatConfig | GroovesConfig | SawtoothConfig | PolylineConfig, Field(discriminator="kind")
]
_ADAPTER: TypeAdapter[Any] = TypeAdapter(SubstrateConfig)


_KINDS = ("flat", "grooves", "sawtooth", "polyline")


def parse_substrate(
    table: Mapping[str, Any],
) -> FlatConfig | GroovesConfig | SawtoothConfig | PolylineConfig:
    """Validate a ``[substrate]`` table and check its geometry; raise a one-line InputError."""
    if not isinstance(table, Mapping):
        raise InputError(f"substrate must be a table (kind = ..., ...), got {table!r}")
    try:
        cfg = _ADAPTER.validate_python(dict(table))
    except ValidationError as exc:
        err = exc.errors()[0]
        if err["type"] in ("union_tag_invalid", "union_tag_not_found"):
            kinds = ", ".join(sorted(_KINDS))
            if "kind" not in table:
                raise InputError(f"substrate.kind is missing (one of {kinds})") from None
            raise InputError(f"substrate.kind: {table['kind']!r} is not one of {kinds}") from None
        loc = [str(x) for x in err["loc"]]
        if loc and loc[0] in _KINDS:  # the union's tag, not a key of the table
            loc = loc[1:]
        raise InputError(f"substrate.{'.'.join(loc) or 'kind'}: {err['msg']}") from None
    cfg.build()  # geometric checks that pydantic cannot express (width < pitch, fillets, ...)
    return cfg
