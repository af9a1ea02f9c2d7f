"""Declarations of the variables of a result dataset: each one's name, dimensions, unit,
meaning and how it is computed, spelled once; the dataset and its reference table are
both made from them (``reduced.nc``: :data:`bristlecrawler.io.netcdf.REDUCED_VARIABLES`;
``drag.nc``: :data:`bristlecrawler.crawler.drag_analysis.DRAG_VARIABLES`)."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np


@dataclass(frozen=True)
class Variable:
    """One variable of a result dataset.

    Attributes:
        name: the variable's name.
        dims: its dimensions.
        unit: its ``units`` attribute ("": a code or an index, no unit).
        description: its ``long_name`` attribute.
        value: its values, from what the dataset is made of (the writer's source).
        flags: the meanings of its codes, by value (``flag_values``, ``flag_meanings``).
        when: whether the source has it (None: always).
        more: more attributes, from the source (a texture law's pitch beside its values).
    """

    name: str
    dims: tuple[str, ...]
    unit: str
    description: str
    value: Callable[[Any], Any]
    flags: tuple[tuple[int, str], ...] = ()
    when: Callable[[Any], bool] | None = None
    more: Callable[[Any], dict[str, Any]] | None = None

    def attrs(self) -> dict[str, Any]:
        """The variable's attributes in the dataset."""
        out: dict[str, Any] = {"long_name": self.description}
        if self.unit:
            out["units"] = self.unit
        if self.flags:
            out["flag_values"] = np.array([v for v, _ in self.flags], dtype=np.int8)
            out["flag_meanings"] = " ".join(m for _, m in self.flags)
        return out

    def variable(self, source) -> tuple[tuple[str, ...], Any, dict[str, Any]]:
        """``(dims, values, attrs)``, the form an ``xarray.Dataset`` takes."""
        more = self.more(source) if self.more is not None else {}
        return self.dims, self.value(source), self.attrs() | more


def variables_markdown(variables: Sequence[Variable]) -> str:
    """The reference table of ``variables`` (Markdown)."""
    rows = ["| variable | dims | unit | meaning |", "|---|---|---|---|"]
    for v in variables:
        meaning = v.description
        if v.flags:
            meaning += ": " + ", ".join(f"{code} {m.replace('_', ' ')}" for code, m in v.flags)
        if v.when is not None:
            meaning += " (only where the run has it)"
        meaning = meaning.replace("|", "\\|")
        rows.append(f"| `{v.name}` | {', '.join(v.dims)} | {v.unit} | {meaning} |")
    return "\n".join(rows) + "\n"
