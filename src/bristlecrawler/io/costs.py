"""Measured costs of earlier runs on this machine, for the estimates a long command prints
before it starts (how long compiling, a scenario, a part of ``reproduce`` took here).

One small JSON file, ``$BRISTLECRAWLER_COSTS`` or ``<cache>/bristlecrawler/costs.json``
(``<cache>``: ``$XDG_CACHE_HOME`` or ``~/.cache``): ``{kind: {key: {"seconds", "utc"}}}``.
An estimate is a convenience: a file that cannot be read or written is ignored.
"""

from __future__ import annotations

import datetime as _dt
import hashlib
import json
import os
from dataclasses import dataclass
from pathlib import Path


def costs_path() -> Path:
    """Where the measured costs are kept."""
    given = os.environ.get("BRISTLECRAWLER_COSTS")
    if given:
        return Path(given).expanduser()
    base = Path(os.environ.get("XDG_CACHE_HOME", Path.home() / ".cache"))
    return base / "bristlecrawler" / "costs.json"


def digest(value: object) -> str:
    """A short key for any JSON-able value (a configuration, a structure)."""
    text = json.dumps(value, sort_keys=True, default=repr)
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def _load() -> dict:
    try:
        data = json.loads(costs_path().read_text())
    except (OSError, ValueError):
        return {}
    return data if isinstance(data, dict) else {}


@dataclass(frozen=True)
class Measured:
    """A cost measured here: ``seconds`` on the date ``utc`` (ISO, UTC)."""

    seconds: float
    utc: str


def recorded(kind: str, key: str) -> Measured | None:
    """The last measured cost of ``key`` (a kind of work: ``compile``, ``simulate``, ...),
    or None."""
    entry = _load().get(kind, {}).get(key)
    try:
        seconds = float(entry["seconds"])
    except (TypeError, KeyError, ValueError):
        return None
    return Measured(seconds, str(entry.get("utc", ""))) if seconds >= 0 else None


def record(kind: str, key: str, seconds: float) -> None:
    """Keep ``seconds`` as the cost of ``key``; finite, non-negative costs only."""
    if not (seconds == seconds and 0 <= seconds < float("inf")):
        return
    from bristlecrawler.io.atomic import atomic_write_text

    data = _load()
    utc = _dt.datetime.now(_dt.UTC).isoformat(timespec="minutes")
    data.setdefault(kind, {})[key] = {"seconds": round(float(seconds), 2), "utc": utc}
    path = costs_path()
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        atomic_write_text(path, json.dumps(data, indent=1, sort_keys=True))
    except OSError:
        pass


def duration(seconds: float) -> str:
    """``about 40 s``, ``about 12 min``, ``about 1.5 h``."""
    if seconds < 90:
        return f"about {max(seconds, 1):.0f} s"
    if seconds < 5400:
        return f"about {seconds / 60:.0f} min"
    return f"about {seconds / 3600:.1f} h"
