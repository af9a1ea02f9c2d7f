"""TOML form of a substrate: each kind's settings declared once, its table generated.

A ``[substrate]`` table names its ``kind`` and the settings of that kind, for example::

    [substrate]
    kind = "grooves"
    width = 1.0      # mm
    depth = 0.25     # mm
    pitch = 2.0      # mm

The friction coefficient is not a property of the shape: it is ``[contact] mu``.

Each kind is a frozen dataclass of settings (:func:`~bristlecrawler.fe.options.setting`:
meaning, unit, range) whose ``build()`` returns the substrate of
:mod:`bristlecrawler.contact.substrates`; the geometric rules between the settings
(a groove narrower than its pitch, fillets that fit) are the substrate's own, checked
when it is built. :func:`parse_substrate` turns a table (a mapping) into the kind's
generated table, whose ``build()`` returns that substrate; every failure is an
:class:`~bristlecrawler.errors.InputError` with one line naming the offending key.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, fields
from typing import Annotated, Any, ClassVar, Literal

from pydantic import Field, PrivateAttr, TypeAdapter, ValidationError, field_validator

from bristlecrawler.contact.substrates import Flat, Grooves, Polyline, Sawtooth
from bristlecrawler.crawler.parts import MAX_LENGTH
from bristlecrawler.errors import InputError
from bristlecrawler.fe.options import REQUIRED, Settings, setting
from bristlecrawler.scenario.strict import StrictSection, bound_message, section_of


def _level(default: Any, doc: str) -> Any:
    """A level or a position along x, mm: any value within +-MAX_LENGTH."""
    return setting(default, doc, ge=-MAX_LENGTH, le=MAX_LENGTH)


def _size(doc: str) -> Any:
    """A positive size with no default, mm."""
    return setting(REQUIRED, doc, gt=0.0, le=MAX_LENGTH)


class _Kind(Settings):
    """The settings of one substrate kind (a frozen dataclass of settings)."""

    kind: ClassVar[str]
    shape: ClassVar[type]

    def build(self):
        """The substrate (its constructor checks the geometry: one home for those rules)."""
        return self.shape(**{f.name: getattr(self, f.name) for f in fields(self)})

    def check(self, prefix: str = "substrate.") -> None:
        super().check(prefix)

    def rules(self, prefix: str = "substrate.") -> Any:
        """The substrate; InputError for a shape that cannot be built (its own rules)."""
        return self.build()


@dataclass(frozen=True)
class FlatSettings(_Kind):
    """A flat plane."""

    kind: ClassVar[str] = "flat"
    shape: ClassVar[type] = Flat

    height: float = _level(0.0, "surface level, mm")


@dataclass(frozen=True)
class GroovesSettings(_Kind):
    """Rectangular grooves (the paper's substrate)."""

    kind: ClassVar[str] = "grooves"
    shape: ClassVar[type] = Grooves

    width: float = _size("groove width, mm")
    depth: float = _size("groove depth, mm")
    pitch: float = _size("groove spacing, mm")
    phase: float = _level(0.0, "x of a groove's left wall, mm")
    top: float = _level(0.0, "land level, mm")
    fillet_top: float = setting(0.0, "radius of the convex land corners, mm", ge=0.0, le=MAX_LENGTH)
    fillet_bottom: float = setting(
        0.0, "radius of the concave bottom corners, mm", ge=0.0, le=MAX_LENGTH
    )


@dataclass(frozen=True)
class SawtoothSettings(_Kind):
    """Asymmetric teeth."""

    kind: ClassVar[str] = "sawtooth"
    shape: ClassVar[type] = Sawtooth

    pitch: float = _size("tooth spacing, mm")
    height: float = _size("tooth height, mm")
    rise_fraction: float = setting(0.8, "fraction of the pitch rising, -", ge=0.0, le=1.0)
    phase: float = _level(0.0, "x of a valley, mm")
    base: float = _level(0.0, "valley level, mm")


@dataclass(frozen=True)
class PolylineSettings(_Kind):
    """Periodic polyline over one period."""

    kind: ClassVar[str] = "polyline"
    shape: ClassVar[type] = Polyline

    points: tuple[tuple[float, float], ...] = setting(
        REQUIRED, "[[x, y], ...] over exactly one period, mm"
    )

    def rules(self, prefix: str = "substrate.") -> Polyline:
        if len(self.points) < 2:
            raise InputError(f"{prefix}points needs at least 2 points, got {len(self.points)}")
        far = [v for p in self.points for v in p if not abs(v) <= MAX_LENGTH]
        if far:
            raise InputError(f"{prefix}points must be within +-{MAX_LENGTH:g} mm, got {far[0]}")
        return self.build()


#: The substrate kinds' settings, in the order the scenario reference lists them.
KINDS: dict[str, type[_Kind]] = {
    k.kind: k for k in (GroovesSettings, FlatSettings, SawtoothSettings, PolylineSettings)
}


class _Table(StrictSection):
    """A substrate table: its kind's settings, checked and built once."""

    #: The settings of the table's kind.
    kind_settings: ClassVar[type[_Kind]]
    _built: Any = PrivateAttr(default=None)

    def settings(self) -> _Kind:
        """The table as its kind's settings."""
        return self.kind_settings(**self.model_dump(exclude={"kind"}))

    def build(self):
        """The substrate of this table (built once, when the table was checked)."""
        if self._built is None:
            self._built = self.settings().build()
        return self._built


def _pairs(cls, value):
    # TOML gives [[x, y], ...] as lists (a caller may give an array); strict mode
    # takes tuples of Python floats only.
    if hasattr(value, "tolist"):
        value = value.tolist()
    if isinstance(value, list | tuple):
        return tuple(tuple(p) if isinstance(p, list) else p for p in value)
    return value


def _table(settings: type[_Kind]) -> type[_Table]:
    """The ``[substrate]`` table of one kind, generated from its settings."""
    kind = (Literal[settings.kind], setting(REQUIRED, "the substrate's kind"))

    def rules(table: _Table) -> None:
        # The ranges are the table's own; the rules between settings are the shape's,
        # checked as it is built, once.
        table._built = table.settings().rules()

    extra = {}
    if settings is PolylineSettings:
        extra["_points"] = field_validator("points", mode="before")(_pairs)
    model = section_of(
        settings,
        _Table,
        settings.__doc__,
        extra={"kind": kind},
        rules=rules,
        validators=extra,
        name=settings.__name__.replace("Settings", "Config"),
    )
    model.kind_settings = settings
    return model


GroovesConfig = _table(GroovesSettings)
FlatConfig = _table(FlatSettings)
SawtoothConfig = _table(SawtoothSettings)
PolylineConfig = _table(PolylineSettings)

#: Substrate kinds and their tables, in the order the reference lists them.
SUBSTRATE_KINDS: dict[str, type[StrictSection]] = {
    "grooves": GroovesConfig,
    "flat": FlatConfig,
    "sawtooth": SawtoothConfig,
    "polyline": PolylineConfig,
}

SubstrateConfig = Annotated[
    FlatConfig | GroovesConfig | SawtoothConfig | PolylineConfig,  # type: ignore[valid-type]
    Field(discriminator="kind"),
]
_ADAPTER: TypeAdapter[Any] = TypeAdapter(SubstrateConfig)


def parse_substrate(table: Mapping[str, Any]) -> Any:
    """Validate a ``[substrate]`` table and check its geometry; raise a one-line InputError."""
    if not isinstance(table, Mapping):
        raise InputError(f"substrate must be a table (kind = ..., ...), got {table!r}")
    try:
        return _ADAPTER.validate_python(dict(table))
    except ValidationError as exc:
        err = exc.errors()[0]
        if err["type"] in ("union_tag_invalid", "union_tag_not_found"):
            kinds = ", ".join(sorted(KINDS))
            if "kind" not in table:
                raise InputError(f"substrate.kind is missing (one of {kinds})") from None
            raise InputError(f"substrate.kind: {table['kind']!r} is not one of {kinds}") from None
        if err["type"] == "value_error":  # the kind's own check: its one line as it is
            raise InputError(str(err["msg"]).removeprefix("Value error, ")) from None
        loc = [str(x) for x in err["loc"]]
        if loc and loc[0] in KINDS:  # the union's tag, not a key of the table
            loc = loc[1:]
        raise InputError(f"substrate.{'.'.join(loc) or 'kind'}: {_message(err)}") from None


def _message(err: dict) -> str:
    """A bound's message as every other key's (``must be <= 1e+04, got 1e+308``, what
    the key is), else pydantic's own."""
    bound = bound_message(err)
    loc = [str(x) for x in err["loc"]]
    if bound is None or len(loc) < 2 or loc[0] not in KINDS:
        return str(err["msg"])
    what = SUBSTRATE_KINDS[loc[0]].model_fields[loc[1]].description
    return f"{bound} ({what})"
