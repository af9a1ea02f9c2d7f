"""Every key of a scenario file, read from the schema: its unit, default and meaning,
and whether it is structural (designs that differ in it need their own compiled program).

``bristlecrawler scenario keys`` prints this table, and the documentation's scenario
reference is generated from it, so neither can drift from the schema. The ``paper``
column shows where the shipped ``paper`` scenario sets another value than the default.
"""

from __future__ import annotations

import math
import re
import typing
from dataclasses import dataclass
from typing import Any, Literal

from pydantic import BaseModel

from bristlecrawler.scenario.schema import Scenario
from bristlecrawler.scenario.substrate import SUBSTRATE_KINDS

_UNITS = (
    "mm/s^2",
    "mm/s",
    "samples/s",
    "t/mm^3",
    "N/mm",
    "1/s",
    "MPa",
    "mJ",
    "mm",
    "Hz",
    "N",
    "s",
    "t",
    "degrees",
)
_UNIT_RE = re.compile(
    r",\s*(" + "|".join(re.escape(u) for u in _UNITS) + r"|-|dimensionless)(?=$|[\s:;.(])"
)
_NO_DEFAULT = object()


class _NotApplicable:
    def __repr__(self) -> str:
        return "NA"


#: The ``paper`` value of a key that the ``paper`` scenario does not have (another
#: substrate kind).
NA: Any = _NotApplicable()


@dataclass(frozen=True)
class Key:
    """One key of a scenario file."""

    key: str  #: dotted name, ``section.key`` (``substrate.width``)
    type: str  #: ``float``, ``int``, ``bool``, ``str`` or the allowed words
    unit: str  #: ``mm``, ``N``, ... or ``-`` for a number without unit, ``""`` for words
    default: Any  #: the schema's default (``None``: null)
    required: bool  #: no default: the table must give it
    paper: Any  #: the shipped ``paper`` scenario's value (:data:`NA` where it has none)
    meaning: str  #: the field's description, without its unit
    kind: str = ""  #: the substrate kind the key belongs to (``""`` for other sections)
    #: whether the key shapes the compiled programs: designs that differ in it cannot
    #: run side by side in one batch (see :mod:`bristlecrawler.crawler.structure`)
    structural: bool = False


def unit_of(description: str) -> str:
    """The unit a field description names after a comma (``"groove width, mm"``)."""
    m = _UNIT_RE.search(description or "")
    if m is None:
        return ""
    return "-" if m.group(1) == "dimensionless" else m.group(1)


def field_meaning(description: str, unit: str) -> str:
    """A setting's description without the unit it names (``, mm``), capitalised."""
    text = (description or "").strip()
    if unit:
        text = _UNIT_RE.sub("", text, count=1).strip()
    return text[:1].upper() + text[1:] if text else ""


def is_structural(field: Any) -> bool:
    """Whether a schema field comes from a setting declared structural."""
    extra = field.json_schema_extra
    return isinstance(extra, dict) and bool(extra.get("structural"))


def _type_name(annotation: Any) -> str:
    origin = typing.get_origin(annotation)
    if origin is Literal:
        return " | ".join(f'"{a}"' for a in typing.get_args(annotation))
    args = [a for a in typing.get_args(annotation) if a is not type(None)]
    if origin is not None and args and origin not in (list, tuple):
        return _type_name(args[0])  # X | None
    if origin in (list, tuple):
        return "list of [x, y]"
    return getattr(annotation, "__name__", str(annotation))


def _rows(model: type[BaseModel], prefix: str, defaults: Any, paper: Any, kind: str = ""):
    for name, field in model.model_fields.items():
        if name == "kind" and kind:
            continue
        annotation = field.annotation
        if isinstance(annotation, type) and issubclass(annotation, BaseModel):
            yield from _rows(annotation, f"{prefix}{name}.", getattr(defaults, name), None)
            continue
        required = field.is_required()
        default = getattr(defaults, name, _NO_DEFAULT) if defaults is not None else _NO_DEFAULT
        if default is _NO_DEFAULT:
            default = None if required else field.default
        unit = unit_of(field.description or "")
        yield Key(
            key=f"{prefix}{name}",
            type=_type_name(annotation),
            unit=unit,
            default=default,
            required=required and defaults is None,
            paper=NA if paper is None else getattr(paper, name, NA),
            meaning=field_meaning(field.description or "", unit),
            kind=kind,
            structural=is_structural(field),
        )


def scenario_keys() -> list[Key]:
    """Every key of a scenario file, section by section, then the substrate kinds'."""
    from bristlecrawler.scenario.load import load_scenario

    default, paper = Scenario(), load_scenario("paper")
    keys: list[Key] = []
    fields = Scenario.model_fields
    for name, field in fields.items():
        annotation = field.annotation
        if not (isinstance(annotation, type) and issubclass(annotation, BaseModel)):
            if name != "substrate":
                keys += _rows_top(name, field, default, paper)
    for name, field in fields.items():
        annotation = field.annotation
        if name == "substrate":
            keys.append(
                Key(
                    "substrate.kind",
                    _type_name(Literal[tuple(SUBSTRATE_KINDS)]),
                    "",
                    default.substrate.kind,
                    False,
                    paper.substrate.kind,
                    "Texture of the rigid substrate; the other substrate keys depend on it",
                    structural=True,
                )
            )
            for kind, model in SUBSTRATE_KINDS.items():
                same = default.substrate.kind == kind
                keys += _rows(
                    model,
                    "substrate.",
                    default.substrate if same else None,
                    paper.substrate if paper.substrate.kind == kind else None,
                    kind,
                )
        elif isinstance(annotation, type) and issubclass(annotation, BaseModel):
            keys += _rows(annotation, f"{name}.", getattr(default, name), getattr(paper, name))
    return keys


def _rows_top(name, field, default, paper):
    unit = unit_of(field.description or "")
    return [
        Key(
            name,
            _type_name(field.annotation),
            unit,
            getattr(default, name),
            False,
            getattr(paper, name),
            field_meaning(field.description or "", unit),
            structural=is_structural(field),
        )
    ]


def toml_value(value: Any) -> str:
    """A value as TOML writes it (``inf``, ``true``, ``"text"``, ``[[0.0, 1.0]]``)."""
    if value is None:
        return "null"
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        if math.isinf(value):
            return "inf" if value > 0 else "-inf"
        return repr(value)
    if isinstance(value, int):
        return str(value)
    if isinstance(value, str):
        return '"' + value.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(value, list | tuple):
        return "[" + ", ".join(toml_value(v) for v in value) + "]"
    return str(value)


def differs(key: Key) -> bool:
    """Whether the shipped ``paper`` scenario sets another value than the default."""
    if key.paper is NA or key.required:
        return False
    return toml_value(key.paper) != toml_value(key.default)


def keys_markdown(keys: list[Key] | None = None) -> str:
    """The scenario reference tables in Markdown: one table per section."""
    keys = scenario_keys() if keys is None else keys
    out: list[str] = []
    section = None
    for k in keys:
        head = k.key.split(".")[0] if "." in k.key else "top level"
        if k.kind:
            head = f'substrate, kind = "{k.kind}"'
        if head != section:
            section = head
            title = f"`[{head}]`" if "." in k.key and not k.kind else head
            if k.kind:
                title = f'`[substrate]` with `kind = "{k.kind}"`'
            elif k.key == "substrate.kind":
                title = "`[substrate]`"
            out += ["", f"### {title}", ""]
            out.append("| key | type | unit | default | `paper` | meaning | structural |")
            out.append("|---|---|---|---|---|---|---|")
        default = "required" if k.required else f"`{toml_value(k.default)}`"
        paper = "" if k.paper is NA else f"`{toml_value(k.paper)}`"
        if differs(k):
            paper = f"**{paper}**"
        typ = k.type.replace("|", "\\|")
        name = k.key.split(".", 1)[1] if "." in k.key else k.key
        meaning = k.meaning.replace("|", "\\|")
        structural = "yes" if k.structural else ""
        out.append(
            f"| `{name}` | {typ} | {k.unit} | {default} | {paper} | {meaning} | {structural} |"
        )
    return "\n".join(out).lstrip("\n") + "\n"


def scenario_toml(scenario: Scenario) -> str:
    """A scenario as TOML text with every key, which loads back to the same scenario (a
    key without a value, ``null``, is written as a comment)."""
    data = scenario.model_dump()
    lines: list[str] = []
    tables = {k: v for k, v in data.items() if isinstance(v, dict)}
    for key, value in data.items():
        if key not in tables:
            lines.append(_toml_line(key, value))
    for name, table in tables.items():
        lines += ["", f"[{name}]"]
        lines += [_toml_line(key, value) for key, value in table.items()]
    return "\n".join(lines) + "\n"


def _toml_line(key: str, value: Any) -> str:
    if value is None:
        return f"# {key} = (not set)"
    return f"{key} = {toml_value(value)}"


def defaults_unlike_paper(document: dict[str, Any]) -> list[Key]:
    """The keys a scenario document leaves to a default that the ``paper`` scenario
    changes (``document`` as written, with its base merged in: see
    :func:`~bristlecrawler.scenario.load.scenario_document`)."""
    out = []
    substrate_kind = (document.get("substrate") or {}).get("kind", "grooves")
    for key in scenario_keys():
        if key.key in ("name", "description") or not differs(key):
            continue
        if key.kind and key.kind != substrate_kind:
            continue
        node: Any = document
        for part in key.key.split("."):
            node = node.get(part, _NO_DEFAULT) if isinstance(node, dict) else _NO_DEFAULT
        if node is _NO_DEFAULT:
            out.append(key)
    return out


#: The commands whose options are tables generated from declared settings: command ->
#: (module, table, the option a key is spelled as where it is not ``--key-name``).
COMMAND_TABLES: dict[str, tuple[str, str]] = {
    "reduced": ("bristlecrawler.scenario.reduced", "ReducedConfig"),
    "drag": ("bristlecrawler.scenario.drag", "DragOptions"),
    "analyze": ("bristlecrawler.scenario.experiment", "AnalyzeOptions"),
    "synth-recording": ("bristlecrawler.scenario.experiment", "SynthOptions"),
}

_RANGE = (("gt", ">"), ("ge", ">="), ("lt", "<"), ("le", "<="))


def command_table(command: str) -> type[BaseModel]:
    """The option table of ``command`` (see :data:`COMMAND_TABLES`)."""
    import importlib

    module, name = COMMAND_TABLES[command]
    return getattr(importlib.import_module(module), name)


def _range_text(field: Any) -> str:
    parts = [
        f"{op} {getattr(m, key):g}"
        for m in field.metadata
        for key, op in _RANGE
        if getattr(m, key, None) is not None
    ]
    return ", ".join(parts)


def _default_text(value: Any) -> str:
    if value is None:
        return ""
    if isinstance(value, float):
        return f"{value:g}"
    return str(value)


def options_markdown(command: str) -> str:
    """The table of a command's options that are declared settings: option, unit,
    default, range and meaning, from the declarations its option table is generated
    from."""
    from bristlecrawler.scenario.strict import option_names

    table = command_table(command)
    names = option_names(table)
    out = ["| option | unit | default | range | meaning |", "|---|---|---|---|---|"]
    for name, field in table.model_fields.items():
        unit = unit_of(field.description or "")
        meaning = field_meaning(field.description or "", unit)
        default = _default_text(field.default)
        if field.default is None and "; None: " in meaning:
            meaning, default = meaning.split("; None: ", 1)
        annotation = field.annotation
        words = typing.get_args(annotation) if typing.get_origin(annotation) is Literal else ()
        allowed = " \\| ".join(f"`{w}`" for w in words) or _range_text(field)
        meaning = meaning.replace("|", "\\|")
        out.append(f"| `{names[name]}` | {unit} | {default} | {allowed} | {meaning} |")
    return "\n".join(out) + "\n"
