"""Small input checks shared by the reduced-model classes."""

from __future__ import annotations

import numpy as np

from bristlecrawler.errors import InputError


def positive(name: str, value: float) -> float:
    """``value`` as a float; InputError naming ``name`` unless it is finite and > 0."""
    value = float(value)
    if not np.isfinite(value) or value <= 0.0:
        raise InputError(f"{name} must be a positive finite number, got {value!r}")
    return value
