"""Loading scenarios from the shipped set or from TOML files, with one-line errors."""

from __future__ import annotations

import os
import tomllib
from importlib import resources
from pathlib import Path
from typing import Any

from bristlecrawler.errors import InputError
from bristlecrawler.scenario.schema import Scenario
from bristlecrawler.scenario.strict import parse_model
from bristlecrawler.scenario.substrate import parse_substrate


def available_scenarios() -> list[str]:
    """Names of the scenarios shipped with the package."""
    folder = resources.files("bristlecrawler") / "scenarios"
    return sorted(p.name[:-5] for p in folder.iterdir() if p.name.endswith(".toml"))


def scenario_from_dict(data: dict[str, Any], origin: str = "scenario") -> Scenario:
    """Validate a mapping (e.g. a parsed TOML document) into a :class:`Scenario`."""
    try:
        if "substrate" in data:
            parse_substrate(data["substrate"])  # its own, more specific messages
        return parse_model(Scenario, data)
    except InputError as exc:
        raise InputError(f"{origin}: {exc}") from None


def load_scenario(name_or_path: str | os.PathLike) -> Scenario:
    """A shipped scenario by name (``paper``, ``paper-vertical``) or a TOML file."""
    text = os.fspath(name_or_path)
    if text.endswith(".toml") or os.sep in text or Path(text).exists():
        path = Path(text)
        if not path.is_file():
            raise InputError(f"scenario file not found: {path}")
        try:
            data = tomllib.loads(path.read_text(encoding="utf-8"))
        except tomllib.TOMLDecodeError as exc:
            raise InputError(f"{path}: invalid TOML ({exc})") from None
        except UnicodeDecodeError:
            raise InputError(f"{path}: not a UTF-8 text file") from None
        base = Path(path).parent
        act = data.get("actuation", {})
        if isinstance(act, dict) and act.get("history") and not Path(act["history"]).is_absolute():
            act["history"] = str(base / act["history"])
        return scenario_from_dict(data, str(path))
    names = available_scenarios()
    if text not in names:
        raise InputError(
            f"unknown scenario '{text}' (shipped: {', '.join(names)}; or a .toml file)"
        )
    resource = resources.files("bristlecrawler") / "scenarios" / f"{text}.toml"
    return scenario_from_dict(tomllib.loads(resource.read_text(encoding="utf-8")), text)


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
        values[key.strip()] = value
    return apply_values(sc, values)


def apply_values(sc: Scenario, values: dict[str, Any]) -> Scenario:
    """The scenario with ``{"section.key": value}`` set (Python values, e.g. a path as
    it is) and re-validated; an unknown key or a bad value raises a one-line InputError."""
    data = sc.model_dump()
    for key, value in values.items():
        *path, last = key.split(".")
        node = data
        for part in path:
            if not isinstance(node.get(part), dict):
                raise InputError(f"--set {key}: unknown section {part!r}")
            node = node[part]
        if last not in node:
            raise InputError(f"--set {key}: unknown parameter {last!r}")
        node[last] = value
    return scenario_from_dict(data, "scenario (with --set)")
