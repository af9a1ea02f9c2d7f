"""Loading scenarios from the shipped set or from TOML files, with one-line errors."""

from __future__ import annotations

import os
import tomllib
from importlib import resources
from pathlib import Path
from typing import Any

from bristlecrawler.contact.substrate_config import parse_substrate
from bristlecrawler.errors import InputError
from bristlecrawler.io.config import parse_model
from bristlecrawler.scenario.schema import Scenario, check_substrate_scale


def available_scenarios() -> list[str]:
    """Names of the scenarios shipped with the package."""
    folder = resources.files("bristlecrawler") / "scenarios"
    return sorted(p.name[:-5] for p in folder.iterdir() if p.name.endswith(".toml"))


def scenario_from_dict(data: dict[str, Any], origin: str = "scenario") -> Scenario:
    """Validate a mapping (e.g. a parsed TOML document) into a :class:`Scenario`."""
    try:
        if isinstance(data.get("substrate"), dict):
            try:
                check_substrate_scale(data["substrate"])
            except ValueError as exc:
                raise InputError(str(exc)) from None
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
            data = tomllib.loads(path.read_text(encoding="utf-8-sig"))
        except tomllib.TOMLDecodeError as exc:
            raise InputError(f"{path}: invalid TOML ({exc})") from None
        except UnicodeDecodeError:
            raise InputError(f"{path}: not a UTF-8 text file") from None
        except RecursionError:
            raise InputError(f"{path}: tables or arrays nested too deeply") from None
        except OSError as exc:
            raise InputError(f"cannot read scenario file {path}: {exc.strerror}") from None
        base = Path(path).parent
        act = data.get("actuation", {})
        history = act.get("history") if isinstance(act, dict) else None
        if isinstance(history, str) and history and not Path(history).is_absolute():
            act["history"] = str(base / history)
        return scenario_from_dict(data, str(path))
    names = available_scenarios()
    if text not in names:
        raise InputError(
            f"unknown scenario '{text}' (shipped: {', '.join(names)}; or a .toml file)"
        )
    resource = resources.files("bristlecrawler") / "scenarios" / f"{text}.toml"
    return scenario_from_dict(tomllib.loads(resource.read_text(encoding="utf-8")), text)
