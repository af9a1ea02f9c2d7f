"""From a study to its designs: the base configuration, the axes' values, the layout.

Grid: every combination; each listed or spaced axis is a dimension named by its key,
and the random and lhs axes share one dimension ``sample`` (one joint sample of
``samples`` points, crossed with the other axes). Zip: one dimension ``design``; every
axis gives the same number of values. Designs are numbered in C order over the
dimensions; a design's value of each key is ``Designs.values[key][index]``.
"""

from __future__ import annotations

import copy
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from bristlecrawler.errors import InputError
from bristlecrawler.studies.schema import MAX_DESIGNS, AxisRange, Study

SAMPLE_DIM, DESIGN_DIM = "sample", "design"


@dataclass(frozen=True)
class Base:
    """The model configuration every design starts from, as a plain (JSON-able) dict:
    a scenario's ``model_dump`` (fe) or a :class:`ReducedConfig`'s (reduced)."""

    model: str
    config: dict[str, Any]


@dataclass(frozen=True)
class Designs:
    """The designs of a study. ``dims``: (name, size) in C order; ``coords``: key ->
    (dimension, values along it); ``values``: key -> flat array over all designs."""

    keys: tuple[str, ...]
    dims: tuple[tuple[str, int], ...]
    coords: dict[str, tuple[str, np.ndarray]]
    values: dict[str, np.ndarray]

    @property
    def n(self) -> int:
        return int(np.prod([size for _, size in self.dims]))

    @property
    def shape(self) -> tuple[int, ...]:
        return tuple(size for _, size in self.dims)

    def overrides(self, index: int) -> dict[str, Any]:
        """``{key: value}`` of design ``index``, as Python scalars."""
        return {k: _python(self.values[k][index]) for k in self.keys}

    def label(self, index: int) -> str:
        text = ", ".join(f"{k}={_fmt(v)}" for k, v in self.overrides(index).items())
        return f"design {index} ({text})"


def _python(value: Any) -> Any:
    return value.item() if isinstance(value, np.generic) else value


def _fmt(v) -> str:
    return f"{v:.6g}" if isinstance(v, float) else str(v)


def resolve_base(study: Study, folder: Path | None) -> Base:
    """The base configuration with the study's ``[set]`` values applied and validated."""
    if study.model == "fe":
        from bristlecrawler.scenario.load import apply_values, load_scenario

        base = study.base
        if folder is not None and not Path(base).is_absolute() and (folder / base).is_file():
            base = str(folder / base)
        sc = load_scenario(base)
        for key in study.set:
            _fe_leaf(sc.model_dump(), key, "[set]")
        if study.set:
            sc = apply_values(sc, dict(study.set))
        return Base("fe", sc.model_dump(mode="json"))
    return Base("reduced", _reduced_base(study, folder))


def _reduced_base(study: Study, folder: Path | None) -> dict[str, Any]:
    import tomllib

    from bristlecrawler._files import MAX_SMALL_BYTES, read_text
    from bristlecrawler.scenario.reduced import ReducedConfig
    from bristlecrawler.scenario.strict import parse_model

    data: dict[str, Any] = {}
    if study.base != "paper":
        path = Path(study.base)
        if folder is not None and not path.is_absolute():
            path = folder / path
        if not path.is_file():
            raise InputError(f"reduced base: 'paper' or a TOML file of its options, got {path}")
        try:
            data = tomllib.loads(read_text(path, MAX_SMALL_BYTES))
        except (tomllib.TOMLDecodeError, UnicodeDecodeError) as exc:
            raise InputError(f"{path}: invalid TOML ({exc})") from None
        except OSError as exc:
            raise InputError(f"cannot read reduced base {path}: {exc.strerror or exc}") from None
        data = data.get("reduced", data)
        if not isinstance(data, dict):
            raise InputError(f"{path}: [reduced] must be a table of the reduced model's options")
    for key in list(study.set) + list(study.axes):
        if key not in ReducedConfig.model_fields:
            where = "[set]" if key in study.set else "[axes]"
            raise InputError(
                f"{where} {key}: unknown key of the reduced model "
                f"({', '.join(ReducedConfig.model_fields)})"
            )
    cfg = parse_model(ReducedConfig, data | dict(study.set))
    return cfg.model_dump()


def _fe_leaf(config: dict, key: str, where: str) -> Any:
    """The base value at dotted ``key``; InputError if the key is not a scenario value."""
    node: Any = config
    for part in key.split("."):
        if not isinstance(node, dict) or part not in node:
            raise InputError(f"{where} {key}: unknown scenario key ({part!r})")
        node = node[part]
    if isinstance(node, dict):
        raise InputError(f"{where} {key}: a section, not a value (name one of its keys)")
    return node


def base_value(base: Base, key: str) -> Any:
    if base.model == "fe":
        return _fe_leaf(base.config, key, "[axes]")
    return base.config[key]


def with_overrides(config: dict[str, Any], overrides: dict[str, Any]) -> dict[str, Any]:
    """A copy of the nested scenario ``config`` with dotted ``{key: value}`` set (a renamed
    key under its new name, with a warning)."""
    from bristlecrawler.scenario.load import current_keys

    out = copy.deepcopy(config)
    for key, value in current_keys(overrides).items():
        *path, last = key.split(".")
        node = out
        for part in path:
            node = node[part]
        node[last] = value
    return out


def _spaced(key: str, axis: AxisRange) -> np.ndarray:
    if axis.linspace is not None:
        lo, hi, num = axis.linspace
        return np.linspace(lo, hi, num)
    lo, hi, num = axis.logspace
    return np.geomspace(lo, hi, num)


def _sampled(study: Study) -> dict[str, np.ndarray]:
    """The random and lhs axes' values: one joint sample of ``study.samples`` points."""
    rng = np.random.default_rng(study.seed)
    axes = {k: a for k, a in study.axes.items() if isinstance(a, AxisRange) and a.sampled}
    lhs_keys = [k for k, a in axes.items() if a.kind == "lhs"]
    unit: dict[str, np.ndarray] = {}
    if lhs_keys:
        from scipy.stats import qmc

        u = qmc.LatinHypercube(d=len(lhs_keys), seed=rng).random(study.samples)
        unit |= {k: u[:, j] for j, k in enumerate(lhs_keys)}
    for k, a in axes.items():
        if a.kind == "random":
            unit[k] = rng.uniform(size=study.samples)
    out = {}
    for k, a in axes.items():
        lo, hi = a.random or a.lhs
        u = unit[k]
        out[k] = np.exp(np.log(lo) + u * np.log(hi / lo)) if a.log else lo + u * (hi - lo)
    return out


def _typed(key: str, values: np.ndarray, like: Any, rounded: bool) -> np.ndarray:
    """Values in the type of the base value: an integer key takes integers."""
    if isinstance(like, bool) or not isinstance(like, int):
        if isinstance(like, float) and values.dtype.kind in "iu":
            return values.astype(float)
        return values
    if values.dtype.kind == "f":
        if rounded:
            values = np.round(values)
        bad = values != np.round(values)
        if bad.any():
            raise InputError(f"[axes] {key}: takes integers, got {values[bad][0]:g}")
        return values.astype(np.int64)
    return values


def axis_values(study: Study, base: Base) -> dict[str, np.ndarray]:
    """Each axis's own values (before combination), typed like the base's value."""
    sampled = _sampled(study)
    out = {}
    for key, axis in study.axes.items():
        like = base_value(base, key)
        if isinstance(axis, list):
            out[key] = _typed(key, np.asarray(axis), like, rounded=False)
        elif axis.sampled:
            out[key] = _typed(key, sampled[key], like, rounded=True)
        else:
            out[key] = _typed(key, _spaced(key, axis), like, rounded=False)
    return out


def expand(study: Study, base: Base) -> Designs:
    """The study's designs (grid or zip), before validation."""
    vals = axis_values(study, base)
    keys = tuple(study.axes)
    sampled = [k for k in keys if isinstance(study.axes[k], AxisRange) and study.axes[k].sampled]
    if study.combine == "zip":
        sizes = {k: v.size for k, v in vals.items()}
        if len(set(sizes.values())) != 1:
            text = ", ".join(f"{k}: {n}" for k, n in sizes.items())
            raise InputError(f"combine = 'zip' needs axes of one length, got {text}")
        n = next(iter(sizes.values()))
        coords = {k: (DESIGN_DIM, v) for k, v in vals.items()}
        return Designs(keys, ((DESIGN_DIM, n),), coords, dict(vals))
    dims, coords = [], {}
    for k in keys:
        if k not in sampled:
            dims.append((k, vals[k].size))
            coords[k] = (k, vals[k])
    if sampled:
        dims.append((SAMPLE_DIM, study.samples))
        coords |= {k: (SAMPLE_DIM, vals[k]) for k in sampled}
    total = int(np.prod([float(s) for _, s in dims]))
    if total > MAX_DESIGNS:
        raise InputError(f"the study has {total} designs, more than {MAX_DESIGNS}")
    names = [d for d, _ in dims]
    shape = tuple(s for _, s in dims)
    flat = {}
    for k, (dim, v) in coords.items():
        view = [1] * len(shape)
        view[names.index(dim)] = v.size
        flat[k] = np.broadcast_to(v.reshape(view), shape).ravel()
    return Designs(keys, tuple(dims), coords, flat)
