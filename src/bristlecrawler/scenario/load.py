"""Loading scenarios from the shipped set or from TOML files, with one-line errors.

A scenario file may start from another one with a top-level ``base`` key::

    base = "paper"          # a shipped scenario, or a path to a TOML file
    [bristle]
    alpha_deg = 30.0        # every other value is the base's

Tables are merged key by key over the base's; a ``[substrate]`` table whose ``kind``
differs from the base's replaces it whole. Without ``base`` every key that the file does
not set takes the schema's default (``bristlecrawler scenario keys`` lists both).
"""

from __future__ import annotations

import os
import tomllib
import warnings
from importlib import resources
from pathlib import Path
from typing import Any

from bristlecrawler.errors import InputError
from bristlecrawler.io.output_paths import safe_stem
from bristlecrawler.scenario.schema import Scenario
from bristlecrawler.scenario.strict import parse_model
from bristlecrawler.scenario.substrate import parse_substrate

_MAX_BASES = 8  # a chain of bases longer than this is a loop


def available_scenarios() -> list[str]:
    """Names of the scenarios shipped with the package."""
    folder = resources.files("bristlecrawler") / "scenarios"
    return sorted(p.name[:-5] for p in folder.iterdir() if p.name.endswith(".toml"))


def shipped_scenario_text(name: str) -> str:
    """The TOML text of a shipped scenario, comments included."""
    names = available_scenarios()
    if name not in names:
        shipped = ", ".join(names)
        raise InputError(f"unknown scenario '{name}' (shipped: {shipped}; or a .toml file)")
    resource = resources.files("bristlecrawler") / "scenarios" / f"{name}.toml"
    return resource.read_text(encoding="utf-8")


#: Keys of a scenario file that were renamed or moved to another table: still read
#: (in a file, ``--set``, a study's keys), with a warning line naming the new key.
RENAMED_KEYS = {
    "contact.max_penetration": "contact.penetration_limit",
    "substrate.mu": "contact.mu",
}


class DeprecatedKeyWarning(FutureWarning):
    """A scenario file, ``--set`` or a study uses the old name of a renamed key."""


def current_key(key: str) -> str:
    """The dotted ``key`` under its current name: a renamed one (:data:`RENAMED_KEYS`)
    with a :class:`DeprecatedKeyWarning`, any other as it is."""
    new = RENAMED_KEYS.get(key)
    if new is None:
        return key
    warnings.warn(f"{key} is deprecated: use {new}", DeprecatedKeyWarning, stacklevel=2)
    return new


def current_keys(values: dict[str, Any]) -> dict[str, Any]:
    """``{dotted key: value}`` with the renamed keys under their new names (a warning for
    each); InputError if a value is given under both names."""
    out: dict[str, Any] = {}
    for key, value in values.items():
        new = current_key(key)
        if new in out or (new != key and new in values):
            raise InputError(f"give {new}, not both it and {key}")
        out[new] = value
    return out


def _new_names(data: dict[str, Any]) -> dict[str, Any]:
    """A scenario document with the renamed keys under their new names, in their new
    tables (a warning for each)."""
    for old in RENAMED_KEYS:
        section, key = old.split(".")
        table = data.get(section)
        if not (isinstance(table, dict) and key in table):
            continue
        new = current_key(old)
        new_section, new_key = new.split(".")
        value = table[key]
        data = {**data, section: {k: v for k, v in table.items() if k != key}}
        target = data.get(new_section, {})
        if not isinstance(target, dict):
            raise InputError(f"{new_section} must be a table, got {target!r}")
        if new_key in target:
            raise InputError(f"give {new}, not both it and {old}")
        data[new_section] = {**target, new_key: value}
    return data


def scenario_from_dict(data: dict[str, Any], origin: str = "scenario") -> Scenario:
    """Validate a mapping (e.g. a parsed TOML document) into a :class:`Scenario`."""
    try:
        data = _new_names(data)
        if "substrate" in data:
            # Checked once here, with its own messages; the scenario takes the table as is.
            data = {**data, "substrate": parse_substrate(data["substrate"])}
        return parse_model(Scenario, data)
    except InputError as exc:
        raise InputError(f"{origin}: {exc}") from None


def _is_path(text: str) -> bool:
    # A folder named like a shipped scenario (a run's --out paper) is not a scenario file.
    return text.endswith(".toml") or os.sep in text or Path(text).is_file()


def _read_toml(path: Path) -> dict[str, Any]:
    from bristlecrawler._files import MAX_SMALL_BYTES, read_text

    if not path.exists():
        raise InputError(f"scenario file not found: {path}")
    try:
        data = tomllib.loads(read_text(path, MAX_SMALL_BYTES, encoding="utf-8-sig"))
    except tomllib.TOMLDecodeError as exc:
        raise InputError(f"{path}: invalid TOML ({exc})") from None
    except UnicodeDecodeError:
        raise InputError(f"{path}: not a UTF-8 text file") from None
    except RecursionError:
        raise InputError(f"{path}: tables or arrays nested too deeply") from None
    except OSError as exc:
        raise InputError(f"cannot read scenario file {path}: {exc.strerror or exc}") from None
    act = data.get("actuation", {})
    history = act.get("history") if isinstance(act, dict) else None
    if isinstance(history, str) and history and not Path(history).is_absolute():
        act["history"] = str(path.parent / history)  # relative to the file
    return data


def _merge(base: dict[str, Any], over: dict[str, Any]) -> dict[str, Any]:
    """``over``'s tables merged key by key into ``base``'s (a new dict)."""
    out = dict(base)
    for key, value in over.items():
        old = out.get(key)
        if isinstance(value, dict) and isinstance(old, dict):
            if key == "substrate" and value.get("kind", old.get("kind")) != old.get("kind"):
                out[key] = dict(value)  # another kind of texture: nothing to inherit
            else:
                out[key] = _merge(old, value)
        else:
            out[key] = value
    return out


def _raw(name_or_path: str, origin: Path | None, depth: int = 0) -> dict[str, Any]:
    """The document of a scenario with its ``base`` chain merged in (not validated)."""
    if depth > _MAX_BASES:
        raise InputError(f"scenario base chain longer than {_MAX_BASES} (a loop?)")
    if _is_path(name_or_path):
        path = Path(name_or_path)
        if origin is not None and not path.is_absolute():
            path = origin.parent / path  # a base path is relative to the file naming it
        data, here = _read_toml(path), path
    else:
        data, here = tomllib.loads(shipped_scenario_text(name_or_path)), None
    where = here or name_or_path
    try:
        # Before merging: a file's old key must override its base's new one.
        data = _new_names(data)
    except InputError as exc:
        raise InputError(f"{where}: {exc}") from None
    base = data.pop("base", None)
    if base is None:
        return data
    if not isinstance(base, str) or not base:
        raise InputError(f"{where}: base must be a scenario name or a .toml path, got {base!r}")
    merged = _merge(_raw(base, here, depth + 1), data)
    merged["name"] = data.get("name", safe_stem(here.stem) if here is not None else name_or_path)
    merged["description"] = data.get("description", f"{base} with the changes of {where}")
    return merged


def scenario_document(name_or_path: str | os.PathLike) -> dict[str, Any]:
    """The scenario's TOML document with its ``base`` chain merged in, before validation:
    the keys the user (or the shipped file) wrote, nothing filled from defaults."""
    return _raw(os.fspath(name_or_path), None)


def load_scenario(name_or_path: str | os.PathLike) -> Scenario:
    """A shipped scenario by name (``paper``, ``paper-vertical``) or a TOML file, which may
    name a ``base`` scenario to start from (see the module)."""
    text = os.fspath(name_or_path)
    return scenario_from_dict(scenario_document(text), text)


def apply_overrides(sc: Scenario, assignments: list[str]) -> Scenario:
    """The scenario with ``section.key=value`` assignments (TOML values) applied and
    re-validated; a bad assignment raises a one-line InputError."""
    import tomllib

    values = {}
    for item in assignments:
        key, sep, raw = item.partition("=")
        if not sep or not key.strip():
            raise InputError(f"--set expects section.key=value, got {item!r}")
        try:
            value = tomllib.loads(f"v = {raw.strip()}")["v"]
        except tomllib.TOMLDecodeError:
            value = raw.strip()  # bare words (kind = grooves) are strings
        except RecursionError:
            raise InputError(f"--set {key.strip()}: value nested too deeply") from None
        values[key.strip()] = value
    return apply_values(sc, values)


def apply_values(sc: Scenario, values: dict[str, Any]) -> Scenario:
    """The scenario with ``{"section.key": value}`` set (Python values, e.g. a path as
    it is) and re-validated; an unknown key or a bad value raises a one-line InputError.
    Setting ``substrate.kind`` to another kind starts that table afresh, so the new kind's
    keys follow it."""
    data = sc.model_dump()
    try:
        values = current_keys(values)
    except InputError as exc:
        raise InputError(f"--set: {exc}") from None
    for key, value in values.items():
        *path, last = key.split(".")
        if path == ["substrate"] and last == "kind" and value != data["substrate"]["kind"]:
            data["substrate"] = {"kind": value}  # none of the old kind's keys apply
            continue
        node = data
        for part in path:
            if not isinstance(node.get(part), dict):
                raise InputError(f"--set {key}: unknown section {part!r}")
            node = node[part]
        if last not in node and path != ["substrate"]:  # the substrate's kind checks its keys
            raise InputError(f"--set {key}: unknown parameter {last!r}")
        node[last] = value
    return scenario_from_dict(data, "scenario (with --set)")
