"""Reading recordings from CSV and NI TDMS files (what a cRIO/LabVIEW acquisition writes).

Column / channel names and signs are configurable through :class:`ChannelMap`; the
defaults are ``time_s``, ``left_mm``, ``right_mm`` (and optional ``current_A``, ``s_mm``,
``force_N``). Without a time column the samples are taken as uniform at ``rate_hz``
(100 S/s by default). Every problem is one :class:`InputError` line naming it.
"""

from __future__ import annotations

import csv
import os
from dataclasses import dataclass

import numpy as np

from bristlecrawler.errors import InputError
from bristlecrawler.experiment.recording import DEFAULT_RATE_HZ, Recording


@dataclass(frozen=True)
class ChannelMap:
    """Where each quantity is in a file, and its sign (+1 or -1).

    Attributes:
        time: time column/channel (s); None or missing -> uniform samples at ``rate_hz``.
        left, right: end displacements (mm).
        current, shortening, force: optional channels (A, mm, N); used when present.
        left_sign, right_sign: multiply the raw channel so that motion is positive.
        rate_hz: sample rate when there is no time channel, samples/s.
        group: TDMS group (default: the first group holding the channels).
    """

    time: str | None = "time_s"
    left: str = "left_mm"
    right: str = "right_mm"
    current: str | None = "current_A"
    shortening: str | None = "s_mm"
    force: str | None = "force_N"
    left_sign: float = 1.0
    right_sign: float = 1.0
    rate_hz: float = DEFAULT_RATE_HZ
    group: str | None = None

    def __post_init__(self) -> None:
        for name in ("left_sign", "right_sign"):
            if getattr(self, name) not in (1.0, -1.0):
                raise InputError(f"{name} must be +1 or -1, got {getattr(self, name)}")
        if not np.isfinite(self.rate_hz) or self.rate_hz <= 0:
            raise InputError(f"sample rate must be positive, got {self.rate_hz}")


def _build(columns: dict[str, np.ndarray], cmap: ChannelMap, source: str, dt: float | None):
    available = ", ".join(columns) or "none"
    for role in ("left", "right"):
        if getattr(cmap, role) not in columns:
            raise InputError(
                f"{source}: no {role}-end channel '{getattr(cmap, role)}' (available: {available})"
            )
    n = columns[cmap.left].size
    if cmap.time is not None and cmap.time in columns:
        t = columns[cmap.time]
    else:
        t = np.arange(n) * (dt if dt is not None else 1.0 / cmap.rate_hz)
    opt = {
        role: columns.get(getattr(cmap, role)) if getattr(cmap, role) else None
        for role in ("current", "shortening", "force")
    }
    return Recording(
        t=t,
        left=cmap.left_sign * columns[cmap.left],
        right=cmap.right_sign * columns[cmap.right],
        source=source,
        **opt,
    )


def read_csv(path: str | os.PathLike, cmap: ChannelMap | None = None) -> Recording:
    """Read a CSV recording (header row; '#' comment lines and blank lines are skipped).

    Empty cells and non-numeric cells such as ``nan`` become NaN (sensor dropouts).
    """
    cmap = cmap or ChannelMap()
    path = os.fspath(path)
    if not os.path.isfile(path):
        raise InputError(f"recording not found: {path}")
    try:
        with open(path, newline="", encoding="utf-8-sig") as fh:
            rows = [r for r in csv.reader(fh) if r and not r[0].lstrip().startswith("#")]
    except UnicodeDecodeError:
        raise InputError(f"{path} is not a text CSV file") from None
    except csv.Error as exc:
        raise InputError(f"{path}: not a readable CSV file ({exc})") from None
    except OSError as exc:
        raise InputError(f"cannot read recording {path}: {exc.strerror}") from None
    if len(rows) < 2:
        raise InputError(f"{path}: no data rows")
    header = [h.strip() for h in rows[0]]
    if all(_is_number(h) for h in header if h):
        raise InputError(f"{path}: first row must be a header naming the columns")
    data = np.full((len(rows) - 1, len(header)), np.nan)
    for i, row in enumerate(rows[1:]):
        if len(row) != len(header):
            raise InputError(
                f"{path}, data row {i + 1}: {len(row)} cells, header has {len(header)}"
            )
        for j, cell in enumerate(row):
            cell = cell.strip()
            if cell and _is_number(cell):
                data[i, j] = float(cell)
    columns = {h: data[:, j] for j, h in enumerate(header)}
    if cmap.time and cmap.time in columns and not np.all(np.isfinite(columns[cmap.time])):
        keep = np.isfinite(columns[cmap.time])
        columns = {h: v[keep] for h, v in columns.items()}
    return _build(columns, cmap, path, None)


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def read_tdms(path: str | os.PathLike, cmap: ChannelMap | None = None) -> Recording:
    """Read a TDMS recording with npTDMS. The time base comes from the time channel, else
    from the channels' ``wf_increment`` property, else from ``cmap.rate_hz``."""
    try:
        from nptdms import TdmsFile
    except ImportError:  # pragma: no cover
        raise InputError("reading TDMS needs npTDMS: pip install npTDMS") from None
    cmap = cmap or ChannelMap()
    path = os.fspath(path)
    if not os.path.isfile(path):
        raise InputError(f"recording not found: {path}")
    try:
        tdms = TdmsFile.read(path)
    except Exception as exc:  # npTDMS raises several types for corrupt files
        raise InputError(f"{path} is not a readable TDMS file ({type(exc).__name__})") from None
    groups = tdms.groups()
    if not groups:
        raise InputError(f"{path}: TDMS file has no groups")
    if cmap.group is not None:
        names = [g.name for g in groups]
        if cmap.group not in names:
            raise InputError(f"{path}: no TDMS group '{cmap.group}' (groups: {', '.join(names)})")
        group = tdms[cmap.group]
    else:
        group = next((g for g in groups if cmap.left in [c.name for c in g.channels()]), groups[0])
    columns = {c.name: np.asarray(c[:], dtype=float) for c in group.channels()}
    left = group[cmap.left] if cmap.left in columns else None
    dt = None
    if left is not None and "wf_increment" in left.properties:
        dt = float(left.properties["wf_increment"])
    return _build(columns, cmap, path, dt)


def read_recording(path: str | os.PathLike, cmap: ChannelMap | None = None) -> Recording:
    """Read a CSV or TDMS recording, chosen by the file extension."""
    ext = os.path.splitext(os.fspath(path))[1].lower()
    if ext == ".tdms":
        return read_tdms(path, cmap)
    if ext in (".csv", ".txt", ".dat"):
        return read_csv(path, cmap)
    raise InputError(f"unknown recording format '{ext}' for {path} (use .csv or .tdms)")
