"""The study file (TOML), validated by pydantic: which model, which base, which axes.

```toml
name = "inclination"
model = "fe"                  # "fe" (a scenario) or "reduced" (the reduced model's options)
base = "paper"                # shipped scenario or TOML file; for "reduced": "paper" or a file
combine = "grid"              # "grid": every combination; "zip": the axes side by side
samples = 0                   # points drawn for the random and lhs axes (one joint sample)
seed = 0

[set]                         # fixed values applied to the base first
"actuation.cycles" = 2

[axes]
"bristle.alpha_deg" = { linspace = [0.0, 75.0, 6] }
"substrate.pitch" = [1.5, 2.0, 3.0]
"contact.mu" = { lhs = [0.3, 0.9] }
```
"""

from __future__ import annotations

import math
import tomllib
from importlib import resources
from pathlib import Path
from typing import Any, Literal

from pydantic import (
    BaseModel,
    ConfigDict,
    Field,
    StrictBool,
    StrictFloat,
    StrictInt,
    StrictStr,
    field_validator,
    model_validator,
)

from bristlecrawler.errors import InputError
from bristlecrawler.scenario.strict import SafeName, parse_model

Scalar = bool | int | float | str
MAX_DESIGNS = 50_000_000


class AxisRange(BaseModel):
    """A generated axis: exactly one of ``linspace = [start, stop, num]``, ``logspace =
    [start, stop, num]`` (values, not exponents: both > 0), ``random = [low, high]``
    (uniform, or log-uniform with ``log = true``) or ``lhs = [low, high]`` (a Latin
    hypercube stratum per sample, jointly over every lhs axis)."""

    model_config = ConfigDict(extra="forbid", frozen=True)

    # Strict, as in a scenario file: "yes" is not true, "3" and true are not numbers.
    linspace: tuple[StrictFloat, StrictFloat, StrictInt] | None = None
    logspace: tuple[StrictFloat, StrictFloat, StrictInt] | None = None
    random: tuple[StrictFloat, StrictFloat] | None = None
    lhs: tuple[StrictFloat, StrictFloat] | None = None
    log: StrictBool = False

    @model_validator(mode="after")
    def _one(self) -> AxisRange:
        given = [k for k in ("linspace", "logspace", "random", "lhs") if getattr(self, k)]
        if len(given) != 1:
            raise ValueError("give exactly one of linspace, logspace, random, lhs")
        kind = given[0]
        lo, hi = getattr(self, kind)[:2]
        if not (math.isfinite(lo) and math.isfinite(hi)):
            raise ValueError(f"{kind}: bounds must be finite")
        if kind in ("linspace", "logspace"):
            num = getattr(self, kind)[2]
            if num < 1:
                raise ValueError(f"{kind}: empty range (num = {num})")
            if num > 1 and lo == hi:
                raise ValueError(f"{kind}: empty range ({lo:g} to {hi:g} with {num} points)")
        elif not lo < hi:
            raise ValueError(f"{kind}: empty or inverted range [{lo:g}, {hi:g}]")
        if (kind == "logspace" or self.log) and not (lo > 0 and hi > 0):
            raise ValueError(f"{kind}: a logarithmic range needs positive bounds")
        if self.log and kind in ("linspace", "logspace"):
            raise ValueError("log = true applies to random and lhs axes (use logspace)")
        return self

    @property
    def kind(self) -> str:
        return next(k for k in ("linspace", "logspace", "random", "lhs") if getattr(self, k))

    @property
    def sampled(self) -> bool:
        return self.kind in ("random", "lhs")


class Study(BaseModel):
    """A design study: a base model configuration and the axes varied over it."""

    model_config = ConfigDict(extra="forbid", frozen=True)

    name: SafeName = Field("study", description="name of the study, used in its folder's name")
    description: StrictStr = ""
    model: Literal["fe", "reduced"]
    base: StrictStr = Field("paper", description="shipped scenario or file (fe); 'paper' or a file")
    combine: Literal["grid", "zip"] = "grid"
    samples: StrictInt = Field(0, ge=0, le=MAX_DESIGNS, description="points of random/lhs axes")
    seed: StrictInt = Field(0, ge=0, le=2**63 - 1, description="seed of the random and lhs axes")
    chunk: StrictInt | None = Field(
        None,
        ge=1,
        le=1_000_000,
        description="designs per task [default: fe 1, reduced 20000]",
    )
    set: dict[str, Scalar] = Field(default_factory=dict, description="fixed base values")
    axes: dict[str, list[Scalar] | AxisRange] = Field(min_length=1)

    reduced_solver: Literal["auto", "exact"] = Field(
        "auto",
        description="reduced model: 'auto' takes the closed form where it holds (two "
        "bristles, sin^2 stroke), the exact solver elsewhere; 'exact': always the solver",
    )

    @model_validator(mode="before")
    @classmethod
    def _current_keys(cls, data: Any) -> Any:
        """An FE study's renamed scenario keys under their new names (a warning each), so
        that its designs, outputs and figures use one name."""
        if not (isinstance(data, dict) and data.get("model") == "fe"):
            return data
        from bristlecrawler.scenario.load import current_keys

        data = dict(data)
        for table in ("set", "axes"):
            if isinstance(data.get(table), dict):
                try:
                    data[table] = current_keys(data[table])
                except InputError as exc:
                    raise ValueError(f"[{table}] {exc}") from None
        return data

    @field_validator("axes", mode="before")
    @classmethod
    def _axes(cls, axes: Any) -> Any:
        """Each axis is a list of values or a range table; one clear message for either."""
        from pydantic import ValidationError

        from bristlecrawler.scenario.strict import first_error_message

        if not isinstance(axes, dict):
            return axes
        out = {}
        for key, axis in axes.items():
            if isinstance(axis, list):
                if not axis:
                    raise ValueError(f"{key}: empty list of values")
                kinds = {float if type(v) is int else type(v) for v in axis}
                if len(kinds) > 1 or not kinds <= {bool, float, str}:
                    raise ValueError(
                        f"{key}: values must be numbers, booleans or strings of one type"
                    )
                out[key] = axis
            elif isinstance(axis, dict):
                try:
                    out[key] = AxisRange.model_validate(axis)
                except ValidationError as exc:
                    raise ValueError(f"{key}: {first_error_message(exc)}") from None
            else:
                raise ValueError(f"{key}: a list of values or a table (linspace, logspace, ...)")
        return out

    @model_validator(mode="after")
    def _samples(self) -> Study:
        sampled = [k for k, a in self.axes.items() if isinstance(a, AxisRange) and a.sampled]
        if sampled and self.samples < 1:
            raise ValueError(f"axes {', '.join(sampled)} are sampled: set samples >= 1")
        if not sampled and self.samples:
            raise ValueError("samples is set but no axis is random or lhs")
        both = set(self.set) & set(self.axes)
        if both:
            raise ValueError(f"{', '.join(sorted(both))}: both in [set] and in [axes]")
        return self

    @property
    def tasks_chunk(self) -> int:
        return self.chunk or (1 if self.model == "fe" else 20_000)


def available_studies() -> list[str]:
    """Names of the studies shipped with the package."""
    folder = resources.files("bristlecrawler") / "studies"
    return sorted(p.name[:-5] for p in folder.iterdir() if p.name.endswith(".toml"))


def _parse(text: str, origin: str) -> dict[str, Any]:
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise InputError(f"{origin}: invalid TOML ({exc})") from None


def load_study(name_or_path: str) -> tuple[Study, Path | None]:
    """A shipped study by name or a TOML file; returns the study and its folder (None for a
    shipped one), against which a relative ``base`` file is found."""
    path = Path(name_or_path)
    if name_or_path.endswith(".toml") or path.exists():
        if not path.is_file():
            raise InputError(f"study file not found: {path}")
        from bristlecrawler._files import MAX_SMALL_BYTES, read_text

        try:
            text = read_text(path, MAX_SMALL_BYTES)
        except UnicodeDecodeError:
            raise InputError(f"{path}: not a UTF-8 text file") from None
        except OSError as exc:
            raise InputError(f"cannot read study file {path}: {exc.strerror or exc}") from None
        data, origin, folder = _parse(text, str(path)), str(path), path.parent
    else:
        names = available_studies()
        if name_or_path not in names:
            raise InputError(
                f"unknown study '{name_or_path}' (shipped: {', '.join(names)}; or a .toml file)"
            )
        resource = resources.files("bristlecrawler") / "studies" / f"{name_or_path}.toml"
        data = _parse(resource.read_text(encoding="utf-8"), name_or_path)
        origin, folder = name_or_path, None
    try:
        return parse_model(Study, data), folder
    except InputError as exc:
        raise InputError(f"{origin}: {exc}") from None
