"""Reading recordings from CSV and NI TDMS files (what a cRIO/LabVIEW acquisition writes).

Column / channel names and signs are configurable through :class:`ChannelMap`; the
defaults are ``time_s``, ``left_mm``, ``right_mm`` (and optional ``current_A``, ``s_mm``,
``force_N``). Without a time column the samples are taken as uniform at ``rate_hz``
(100 S/s by default). Every problem is one :class:`InputError` line naming it.
"""

from __future__ import annotations

import csv
import itertools
import os
import warnings
from dataclasses import dataclass

import numpy as np

from bristlecrawler._files import open_regular
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
        named: roles (``"time"``, ``"force"``, ...) the user named, which must be present
            (left and right always must).
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
    named: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        for name in ("left_sign", "right_sign"):
            if getattr(self, name) not in (1.0, -1.0):
                raise InputError(f"{name} must be +1 or -1, got {getattr(self, name)}")
        if not np.isfinite(self.rate_hz) or self.rate_hz <= 0:
            raise InputError(f"sample rate must be positive, got {self.rate_hz}")


def _build(columns: dict[str, np.ndarray], cmap: ChannelMap, source: str, dt: float | None):
    for role in ("left", "right"):
        if getattr(cmap, role) not in columns:
            raise InputError(
                f"{source}: no {role}-end channel '{getattr(cmap, role)}' among its "
                f"{len(columns)} (--{role} names it)"
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


#: Data rows parsed at a time: a large recording is read in chunks of this many rows, so
#: that its text is never held whole (the samples, as float64, are what stays).
CHUNK_ROWS = 65_536
#: The largest recording read: far beyond any test rig's, it only stops a runaway file.
MAX_RECORDING_BYTES = 1 << 36


def read_csv(path: str | os.PathLike, cmap: ChannelMap | None = None) -> Recording:
    """Read a CSV recording (header row; '#' comment lines and blank lines are skipped).

    Empty cells and ``nan`` are sensor dropouts (NaN); other cells that are not numbers
    (``abc``) are read as dropouts too, counted, and reported in one warning.
    """
    cmap = cmap or ChannelMap()
    path = os.fspath(path)
    fd = _open_recording(path)
    try:
        with open(fd, newline="", encoding="utf-8-sig") as fh:
            rows = (r for r in csv.reader(fh) if r and not r[0].lstrip().startswith("#"))
            header = [h.strip() for h in next(rows, [])]
            if header and all(_is_number(h) for h in header if h):
                raise InputError(f"{path}: first row must be a header naming the columns")
            _check_named(header, cmap, path)
            data, junk = _read_rows(rows, header, path)
    except UnicodeDecodeError:
        raise InputError(f"{path} is not a text CSV file") from None
    except csv.Error as exc:
        raise InputError(f"{path}: not a readable CSV file ({exc})") from None
    except OSError as exc:
        raise InputError(f"cannot read recording {path}: {exc.strerror}") from None
    if data.shape[0] == 0:
        raise InputError(f"{path}: no data rows")
    if junk:
        count, first = junk
        warnings.warn(
            f"{path}: {count} cell{'s' if count > 1 else ''} that are not numbers (first: "
            f"{first}) read as dropouts",
            stacklevel=2,
        )
    columns = {h: data[:, j] for j, h in enumerate(header)}
    if cmap.time and cmap.time in columns and not np.all(np.isfinite(columns[cmap.time])):
        keep = np.isfinite(columns[cmap.time])
        columns = {h: v[keep] for h, v in columns.items()}
    return _build(columns, cmap, path, None)


def _open_recording(path: str) -> int:
    """A descriptor of the recording ``path``, checked to be a regular file (a FIFO would
    block the reader forever, a device never end); InputError otherwise."""
    try:
        return open_regular(path, MAX_RECORDING_BYTES)
    except FileNotFoundError:
        raise InputError(f"recording not found: {path}") from None
    except OSError as exc:
        raise InputError(f"cannot read recording {path}: {exc.strerror or exc}") from None


def _read_rows(rows, header: list[str], path: str):
    """The data rows as a float array, parsed CHUNK_ROWS at a time, and (count, where the
    first is) of the cells that are neither numbers, empty nor ``nan``."""
    chunks, count, first, done = [], 0, "", 0
    while True:
        block = list(itertools.islice(rows, CHUNK_ROWS))
        if not block:
            break
        for i, row in enumerate(block):
            if len(row) != len(header):
                raise InputError(
                    f"{path}, data row {done + i + 1}: {len(row)} cells, header has {len(header)}"
                )
        try:
            chunk = np.array(block, dtype=np.float64)
        except ValueError:  # empty or non-numeric cells: the slow way, cell by cell
            chunk, bad = _parse_cells(block, header, done)
            count += len(bad)
            first = first or (bad[0] if bad else "")
        chunks.append(chunk)
        done += len(block)
    data = np.concatenate(chunks) if chunks else np.empty((0, len(header)))
    return data, (count, first) if count else None


def _parse_cells(block: list[list[str]], header: list[str], done: int):
    chunk = np.full((len(block), len(header)), np.nan)
    bad = []
    for i, row in enumerate(block):
        for j, cell in enumerate(row):
            cell = cell.strip()
            if not cell:
                continue
            try:
                chunk[i, j] = float(cell)
            except ValueError:
                # Where, not what: a cell's text is the file's content, not the tool's.
                bad.append(f"data row {done + i + 1}, column {j + 1}")
    return chunk, bad


def _check_named(columns, cmap: ChannelMap, source: str) -> None:
    """InputError for a column the user named (``cmap.named``) that is not there."""
    for role in cmap.named:
        name = getattr(cmap, role)
        if name is not None and name not in columns:
            # The file's own names are not listed: the message names what was asked for.
            raise InputError(f"{source}: no {role} column '{name}' among its {len(columns)}")


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
    os.close(_open_recording(path))
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
            raise InputError(f"{path}: no TDMS group '{cmap.group}' among its {len(names)}")
        group = tdms[cmap.group]
    else:
        group = next((g for g in groups if cmap.left in [c.name for c in g.channels()]), groups[0])
    _check_named([c.name for c in group.channels()], cmap, path)
    columns = {c.name: _numbers(c, i, path) for i, c in enumerate(group.channels())}
    left = group[cmap.left] if cmap.left in columns else None
    dt = None
    if left is not None and "wf_increment" in left.properties:
        dt = float(left.properties["wf_increment"])
    return _build(columns, cmap, path, dt)


def _numbers(channel, i: int, path: str) -> np.ndarray:
    """A TDMS channel's samples as floats; InputError for a channel of text or times."""
    try:
        return np.asarray(channel[:], dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"{path}: TDMS channel {i + 1} does not hold numbers") from None


def read_recording(path: str | os.PathLike, cmap: ChannelMap | None = None) -> Recording:
    """Read a CSV or TDMS recording, chosen by the file extension."""
    ext = os.path.splitext(os.fspath(path))[1].lower()
    if ext == ".tdms":
        return read_tdms(path, cmap)
    if ext in (".csv", ".txt", ".dat"):
        return read_csv(path, cmap)
    raise InputError(f"unknown recording format '{ext}' for {path} (use .csv or .tdms)")
