"""Reading CalculiX's printed results (the ``.dat`` file of ``*NODE PRINT``).

CalculiX writes one block per output request and increment::

     total force (fx,fy,fz) for set CLAMP and time  0.1000000E+01

            1.234E-01 -2.731E-01  0.000E+00

     displacements (vx,vy,vz) for set CARRIAGE and time  0.1000000E+01

             1  1.000E-01 -1.587E-01  0.000E+00

:func:`read_dat` turns them into arrays by time.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

import numpy as np

from bristlecrawler.errors import InputError

_HEADER = re.compile(
    r"^\s*(?P<what>total force|forces|displacements)\s+\([a-z,]+\)\s+for set\s+"
    r"(?P<set>\S+)\s+and time\s+(?P<time>\S+)\s*$"
)


@dataclass(frozen=True)
class Printed:
    """One output request's values over the increments: ``time`` (K,), ``values`` (K, n, 3)
    (a node set's rows; one row for totals), ``nodes`` (n,) (-1 for totals)."""

    time: np.ndarray
    values: np.ndarray
    nodes: np.ndarray


def read_dat(text: str) -> dict[tuple[str, str], Printed]:
    """The blocks of a ``.dat`` file by (kind, set): kind "total force", "forces" or
    "displacements", the set's name in upper case."""
    blocks: dict[tuple[str, str], list] = {}
    lines = text.splitlines()
    i = 0
    while i < len(lines):
        m = _HEADER.match(lines[i])
        i += 1
        if not m:
            continue
        rows = []
        while i < len(lines) and not _HEADER.match(lines[i]):
            parts = lines[i].split()
            i += 1
            if not parts:
                if rows:
                    break
                continue
            try:
                nums = [float(p) for p in parts]
            except ValueError:
                break
            rows.append(nums if len(nums) == 4 else [-1.0, *nums])
        key = (m["what"], m["set"].upper())
        blocks.setdefault(key, []).append((float(m["time"]), rows))
    return {key: _stack(key, items) for key, items in blocks.items()}


def _stack(key, items) -> Printed:
    widths = {len(rows) for _, rows in items}
    if len(widths) != 1 or 0 in widths:
        raise InputError(
            f"the .dat file's {key[0]} for set {key[1]} changes shape between increments"
        )
    t = np.array([time for time, _ in items])
    v = np.array([[row[1:] for row in rows] for _, rows in items])
    nodes = np.array([int(row[0]) for row in items[0][1]])
    return Printed(t, v, nodes)
