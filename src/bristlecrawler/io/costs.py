"""Measured costs of earlier runs on this machine, for the estimates a long command prints
before it starts (how long compiling, a scenario, a part of ``reproduce`` took here).

One small JSON file, ``$BRISTLECRAWLER_COSTS`` or ``<cache>/bristlecrawler/costs.json``
(``<cache>``: ``$XDG_CACHE_HOME`` or ``~/.cache``): ``{kind: {key: {"seconds", "utc"}}}``;
``BRISTLECRAWLER_NO_COSTS=1`` keeps none (the estimates then quote the reference machine).
An estimate is a convenience: a file that cannot be read or written is ignored.

The file is the tool's own, so it is only ever replaced where it is one: written whole
beside it and renamed over it (never written through a link), and only where nothing is
there yet or the user's own regular file of measured costs is. A link, a device, a
folder, another user's file, or a file that holds anything else is left as it is; named
by ``BRISTLECRAWLER_COSTS``, it is refused with one line before a command starts
(:func:`check_costs_env`).
"""

from __future__ import annotations

import datetime as _dt
import hashlib
import json
import os
import stat
from dataclasses import dataclass
from pathlib import Path

from bristlecrawler._files import MAX_SMALL_BYTES, kind, read_bytes, write_private, xdg_home
from bristlecrawler.errors import InputError


def costs_off() -> bool:
    """Whether no costs are kept (``BRISTLECRAWLER_NO_COSTS`` set, and not to 0)."""
    return os.environ.get("BRISTLECRAWLER_NO_COSTS", "").strip() not in ("", "0")


def costs_path() -> Path:
    """Where the measured costs are kept."""
    given = os.environ.get("BRISTLECRAWLER_COSTS")
    if given:
        return Path(given).expanduser()
    return xdg_home("XDG_CACHE_HOME", ".cache") / "bristlecrawler" / "costs.json"


def _is_costs(data: object) -> bool:
    """Whether ``data`` has the shape of the file this module writes."""
    return isinstance(data, dict) and all(
        isinstance(entries, dict)
        and all(isinstance(e, dict) and "seconds" in e for e in entries.values())
        for entries in data.values()
    )


def unfit(path: Path) -> str | None:
    """Why the costs must not be written to ``path`` (see the module), in a few words;
    None where nothing is there yet or the user's own costs file is."""
    try:
        st = os.lstat(path)
    except FileNotFoundError:
        return None
    except OSError as exc:
        return f"it cannot be used ({exc.strerror or exc})"
    if stat.S_ISLNK(st.st_mode):
        return "it is a link"
    if not stat.S_ISREG(st.st_mode):
        return f"it is {kind(st.st_mode)}, not a file"
    if hasattr(os, "getuid") and st.st_uid != os.getuid():
        return "it belongs to another user"
    try:
        data = json.loads(read_bytes(path, MAX_SMALL_BYTES, follow=False))
    except (OSError, ValueError, RecursionError):
        data = None
    if not _is_costs(data):
        return "it is a file this tool did not write (not its measured costs)"
    return None


def check_costs_env() -> None:
    """InputError, one line, where ``BRISTLECRAWLER_COSTS`` names something the costs
    must not be written to: a command refuses it before it starts, as it would an option."""
    given = os.environ.get("BRISTLECRAWLER_COSTS")
    if not given or costs_off():
        return
    reason = unfit(Path(given).expanduser())
    if reason is not None:
        raise InputError(
            f"BRISTLECRAWLER_COSTS={given!r}"[:200] + f" is refused: {reason}; name a new "
            "file for the costs this tool measures, or set BRISTLECRAWLER_NO_COSTS=1 to "
            "keep none"
        )


def digest(value: object) -> str:
    """A short key for any JSON-able value (a configuration, a structure)."""
    text = json.dumps(value, sort_keys=True, default=repr)
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def _load() -> dict:
    path = costs_path()
    if costs_off() or unfit(path) is not None:
        return {}
    try:
        data = json.loads(read_bytes(path, MAX_SMALL_BYTES, follow=False))
    except (OSError, ValueError, RecursionError):
        return {}
    return data if _is_costs(data) else {}


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
    """Keep ``seconds`` as the cost of ``key``; finite, non-negative costs only, and only
    into a costs file of the tool's own (see the module)."""
    if not (seconds == seconds and 0 <= seconds < float("inf")) or costs_off():
        return
    path = costs_path()
    if unfit(path) is not None:
        return
    data = _load()
    utc = _dt.datetime.now(_dt.UTC).isoformat(timespec="minutes")
    data.setdefault(kind, {})[key] = {"seconds": round(float(seconds), 2), "utc": utc}
    try:
        # A new file beside it, renamed over it: a link or a file put there meanwhile is
        # replaced, never written through.
        write_private(path, json.dumps(data, indent=1, sort_keys=True).encode())
    except OSError:
        pass


def duration(seconds: float) -> str:
    """``about 40 s``, ``about 12 min``, ``about 1.5 h``."""
    if seconds < 90:
        return f"about {max(seconds, 1):.0f} s"
    if seconds < 5400:
        return f"about {seconds / 60:.0f} min"
    return f"about {seconds / 3600:.1f} h"
