"""TOML form of a substrate: each kind's table generated from the substrate's own fields.

A ``[substrate]`` table names its ``kind`` and the settings of that kind, for example::

    [substrate]
    kind = "grooves"
    width = 1.0      # mm
    depth = 0.25     # mm
    pitch = 2.0      # mm

The friction coefficient is not a property of the shape: it is ``[contact] mu``.

Each kind is a substrate class of :mod:`bristlecrawler.contact.substrates`, registered
under its kind (:attr:`~bristlecrawler.contact.substrates.Substrate.kinds`), whose fields
are :func:`~bristlecrawler.fe.options.setting` declarations (meaning, unit, range): the
table of each kind is generated from them, one number per field (a list of ``[x, y]``
points for a polyline), and the geometric rules between the fields (a groove narrower than
its pitch, fillets that fit) are the substrate's constructor's, run once as the table is
checked. :func:`parse_substrate` turns a table (a mapping) into the kind's table, whose
``build()`` returns the substrate; every failure is an
:class:`~bristlecrawler.errors.InputError` with one line naming the offending key.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Annotated, Any, ClassVar, Literal, Union

from pydantic import Field, PrivateAttr, TypeAdapter, ValidationError, field_validator

from bristlecrawler.contact.substrates import Polyline, Substrate
from bristlecrawler.errors import InputError
from bristlecrawler.fe.options import REQUIRED, setting, settings_of
from bristlecrawler.scenario.strict import StrictSection, bound_message, section_of

#: The substrate kinds, in the order the scenario reference lists them (the paper's
#: grooves first, then the others as they are declared).
KINDS: dict[str, type[Substrate]] = {
    "grooves": Substrate.kinds["grooves"],
    **{k: c for k, c in Substrate.kinds.items() if k != "grooves"},
}
#: What a scenario table gives for a field that is a point list rather than a number.
_POINTS = tuple[tuple[float, float], ...]


class _Table(StrictSection):
    """A substrate table: its kind's settings, checked and built once."""

    #: The substrate class of the table's kind.
    shape: ClassVar[type[Substrate]]
    _built: Any = PrivateAttr(default=None)

    def build(self) -> Substrate:
        """The substrate of this table (built once, when the table was checked)."""
        if self._built is None:
            self._built = self.shape(**self.model_dump(exclude={"kind"}))
        return self._built


def _pairs(cls, value):
    # TOML gives [[x, y], ...] as lists (a caller may give an array); strict mode
    # takes tuples of Python floats only.
    if hasattr(value, "tolist"):
        value = value.tolist()
    if isinstance(value, list | tuple):
        return tuple(tuple(p) if isinstance(p, list) else p for p in value)
    return value


def _table(shape: type[Substrate]) -> type[_Table]:
    """The ``[substrate]`` table of one kind, generated from its substrate's fields."""
    kind = (Literal[shape.kind], setting(REQUIRED, "the substrate's kind"))
    types = {f.name: _POINTS if shape is Polyline else float for f in settings_of(shape)}

    def rules(table: _Table) -> None:
        # The ranges are the table's own; the rules between settings are the shape's,
        # checked as it is built, once.
        table.build()

    extra = {}
    if shape is Polyline:
        extra["_points"] = field_validator("points", mode="before")(_pairs)
    model = section_of(
        shape,
        _Table,
        shape.__doc__.split("\n\n")[0],
        extra={"kind": kind},
        rules=rules,
        validators=extra,
        name=f"{shape.__name__}Config",
        types=types,
    )
    model.shape = shape
    return model


#: Substrate kinds and their tables, in the order the reference lists them.
SUBSTRATE_KINDS: dict[str, type[StrictSection]] = {k: _table(c) for k, c in KINDS.items()}

SubstrateConfig = Annotated[
    Union[tuple(SUBSTRATE_KINDS.values())],  # type: ignore[valid-type]  # noqa: UP007
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
            raise InputError(_keyed(str(err["msg"]).removeprefix("Value error, "))) from None
        loc = [str(x) for x in err["loc"]]
        if loc and loc[0] in KINDS:  # the union's tag, not a key of the table
            loc = loc[1:]
        raise InputError(f"substrate.{'.'.join(loc) or 'kind'}: {_message(err)}") from None


def _keyed(message: str) -> str:
    """A substrate's own message with the key it starts with named as the table's
    (``points ...`` -> ``substrate.points ...``)."""
    first = message.split(" ", 1)[0].rstrip(":")
    fields = {f for c in KINDS.values() for f in c.__dataclass_fields__}
    return f"substrate.{message}" if first in fields else message


def _message(err: dict) -> str:
    """A bound's message as every other key's (``must be <= 1e+04, got 1e+308``, what
    the key is), else pydantic's own."""
    bound = bound_message(err)
    loc = [str(x) for x in err["loc"]]
    if bound is None or len(loc) < 2 or loc[0] not in KINDS:
        return str(err["msg"])
    what = SUBSTRATE_KINDS[loc[0]].model_fields[loc[1]].description
    return f"{bound} ({what})"
