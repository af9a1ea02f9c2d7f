"""Validation of user input with pydantic, turned into one-line :class:`InputError` messages."""

from __future__ import annotations

import dataclasses
import typing
from typing import Annotated, Any, TypeVar

import numpy as np
from pydantic import (
    AfterValidator,
    BaseModel,
    ConfigDict,
    Field,
    ValidationError,
    create_model,
    model_validator,
)

from bristlecrawler.errors import InputError
from bristlecrawler.io.output_paths import check_safe_name

#: A name that becomes part of a run folder's name (see :data:`io.output_paths.SAFE_NAME`).
SafeName = Annotated[str, AfterValidator(check_safe_name)]

M = TypeVar("M", bound=BaseModel)


class StrictSection(BaseModel):
    """A table of a configuration file: unknown keys refused, frozen, and strict: a number
    must be a number (TOML 45 or 45.0), not a bool or the string "45" (lax mode would take
    ``--set bristle.elements=true`` as one element). A numpy scalar (a sweep's
    ``np.linspace`` value) is taken as its Python number."""

    model_config = ConfigDict(extra="forbid", frozen=True, strict=True)

    @model_validator(mode="before")
    @classmethod
    def _plain_numbers(cls, data):
        if isinstance(data, dict):
            return {k: v.item() if isinstance(v, np.generic) else v for k, v in data.items()}
        return data


def pydantic_field(
    declared: dataclasses.Field, kind: Any, default: Any = dataclasses.MISSING
) -> Any:
    """The pydantic ``Field`` of a setting declared with
    :func:`bristlecrawler.settings.setting`: its default (``default`` instead, if given;
    none for a required one), its meaning as the description and its range as pydantic
    bounds."""
    meta = declared.metadata
    value = declared.default if default is dataclasses.MISSING else default
    extra = dict(meta["bounds"])
    if kind is float or float in typing.get_args(kind):
        extra["allow_inf_nan"] = meta["inf"]
    if meta["structural"]:
        extra["json_schema_extra"] = {"structural": True}
    if value is dataclasses.MISSING:
        return Field(description=meta["doc"], **extra)
    return Field(value, description=meta["doc"], **extra)


def section_of(
    settings: type,
    base: type[BaseModel],
    doc: str,
    *,
    exclude: tuple[str, ...] = (),
    extra: dict[str, tuple[Any, dataclasses.Field]] | None = None,
    rules: Any = None,
    validators: dict[str, Any] | None = None,
    name: str | None = None,
    prefix: str = "",
    types: dict[str, Any] | None = None,
) -> type[BaseModel]:
    """The table (a scenario's section, a command's options) of an options dataclass whose
    fields are declared with :func:`bristlecrawler.settings.setting`: one key per setting
    (but ``exclude``), of the setting's name, type and default, its meaning as the
    description and its range as pydantic bounds; ``extra`` (name -> (type, declared
    setting)) adds the table's own keys in front (a scenario's ``bristle.count``);
    ``types`` (name -> type) gives a key the type its table takes where the dataclass's
    annotation is not it (a substrate's array leaves, one number in a table). After the
    fields (their ranges checked by pydantic), the table's ``rules(table)`` if given, else
    the dataclass's own ``rules(prefix)`` (a :class:`bristlecrawler.settings.Settings`: the
    rules between settings), so each rule has one home and runs once. ``base``: the
    pydantic model the table derives from (:class:`StrictSection` for a scenario's, with
    the table's own methods where it has some)."""
    hints = typing.get_type_hints(settings) | (types or {})
    fields: dict[str, Any] = {
        key: (kind, pydantic_field(declared, kind))
        for key, (kind, declared) in (extra or {}).items()
    }
    for f in dataclasses.fields(settings):
        if "bounds" in f.metadata and f.name not in exclude:
            fields[f.name] = (hints[f.name], pydantic_field(f, hints[f.name]))
    own = set(extra or ())

    def check(self):
        try:
            if rules is not None:
                rules(self)
            else:
                settings(**self.model_dump(exclude=own)).rules(prefix)
        except InputError as exc:
            raise ValueError(str(exc)) from None
        return self

    model = create_model(
        name or settings.__name__ + "Config",
        __base__=base,
        __validators__={"_check": model_validator(mode="after")(check), **(validators or {})},
        **fields,
    )
    model.__doc__ = doc
    return model


def first_error_message(
    exc: ValidationError,
    model: type[BaseModel] | None = None,
    names: dict[str, str] | None = None,
) -> str:
    """One line: the first problem, naming the parameter (as ``names`` spells it, e.g. a
    command-line option), and (given the ``model``) what the parameter is, with its unit,
    from the field's description."""
    err = exc.errors()[0]
    loc = [p for p in err.get("loc", ()) if p != "__root__"]
    msg = bound_message(err) or str(err.get("msg", "invalid value"))
    msg = msg.removeprefix("Value error, ")
    what = _description(model, loc) if model is not None else None
    shown = [names.get(p, p) if names and i == 0 else p for i, p in enumerate(loc)]
    where = f"{'.'.join(str(p) for p in shown)}: " if loc else ""
    if err.get("type") == "value_error" and msg.startswith(where[:-2] + "."):
        where = ""  # a rule's message that names the key in full
    if what and err.get("type") != "value_error":
        msg = f"{msg} ({what})"
    extra = f" (and {len(exc.errors()) - 1} more problems)" if len(exc.errors()) > 1 else ""
    return f"{where}{msg}{extra}"


_BOUNDS = {
    "greater_than": (">", "gt"),
    "greater_than_equal": (">=", "ge"),
    "less_than": ("<", "lt"),
    "less_than_equal": ("<=", "le"),
}


def bound_message(err: dict) -> str | None:
    """``must be <= 1e+07, got 1e+308`` for a bound pydantic checked (its own message
    spells 1e-9 as 0.000000001)."""
    if err.get("type") == "finite_number":
        return f"must be a finite number, got {err.get('input')!r}"
    if err.get("type") not in _BOUNDS:
        return None
    op, key = _BOUNDS[err["type"]]
    bound, value = err.get("ctx", {}).get(key), err.get("input")
    if isinstance(value, int) and not isinstance(value, bool):
        return f"must be {op} {bound:g}, got {value}"
    try:
        return f"must be {op} {bound:g}, got {value:g}"
    except (TypeError, ValueError):
        return None


def _short(description: str) -> str:
    """The first clause of a field description: what it is, and its unit."""
    for stop in (": ", ". ", "; "):
        description = description.split(stop)[0]
    return description if len(description) <= 100 else description[:97] + "..."


def _description(model: type[BaseModel], loc: list) -> str | None:
    """The description of the field at ``loc`` (nested models followed), if any."""
    field = None
    for part in loc:
        fields = getattr(model, "model_fields", None)
        if not isinstance(part, str) or not fields or part not in fields:
            return None
        field = fields[part]
        model = field.annotation
    if field is None or not field.description:
        return None
    return _short(field.description)


def parse_model(model: type[M], data: dict[str, Any], names: dict[str, str] | None = None) -> M:
    """Validate ``data`` into ``model``; raise :class:`InputError` with one line on failure
    (naming a parameter as ``names`` spells it, if given)."""
    try:
        return model.model_validate(data)
    except ValidationError as exc:
        raise InputError(first_error_message(exc, model, names)) from None


def option_names(model: type[BaseModel], **renamed: str) -> dict[str, str]:
    """``{field: "--field-name"}`` for a model filled from command-line options; fields
    whose option is spelt otherwise are given as ``field="--option"``."""
    return {f: renamed.get(f, "--" + f.replace("_", "-")) for f in model.model_fields}
