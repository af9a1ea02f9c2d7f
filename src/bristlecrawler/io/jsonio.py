"""Strict JSON: what every JSON file and ``--json`` line of the package is written with.

JSON has no ``NaN`` or ``Infinity``; Python's ``json`` writes them anyway unless told not
to, and other readers (JavaScript, jq, serde) then refuse the file. A quantity that is not
a finite number (a time not measured, a ratio without data) is written as ``null``.
"""

from __future__ import annotations

import json
import math
from typing import Any


def finite_or_none(value: Any) -> Any:
    """``value`` with every non-finite float (also inside lists, tuples and dicts) as None;
    numpy scalars and arrays become Python numbers and lists."""
    if hasattr(value, "tolist") and not isinstance(value, str):
        value = value.tolist()
    if isinstance(value, float):
        return value if math.isfinite(value) else None
    if isinstance(value, dict):
        return {str(k): finite_or_none(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [finite_or_none(v) for v in value]
    return value


def dumps_strict(value: Any, indent: int | None = None) -> str:
    """Strict JSON text of ``value`` (see the module); other objects as ``str``."""
    return json.dumps(finite_or_none(value), indent=indent, allow_nan=False, default=str)
