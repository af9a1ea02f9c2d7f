"""Figures of a study: each output against each axis, and maps over two axes.

Axis labels come from the declarations: a design axis's meaning and unit from the scenario
schema, an output's from :data:`OUTPUTS`. Designs that failed or were lost have no value;
they are marked on every figure (a red cross at the foot of the panel, or on the map), so
that a curve that stops is not read as the end of the axis.
"""

from __future__ import annotations

import functools
import re
import textwrap
from pathlib import Path

import numpy as np

from bristlecrawler.studies.evaluate import OUTPUTS, DesignStatus

PLOTTED = (
    "net_advance_mm",
    "advance_per_cycle_mm",
    "work_mJ",
    "cost_of_transport_mJ_per_mm",
    "mean_abs_connector_force_N",
    "max_abs_connector_force_N",
)
MAPPED = ("advance_per_cycle_mm", "cost_of_transport_mJ_per_mm")
MAX_POINTS = 20_000
MAX_LINES = 8


def _unit_suffix(unit: str) -> str:
    return "" if unit in ("", "1", "-") else f" ({unit})"


def output_label(out: str) -> str:
    """``net_advance_mm`` -> ``net advance (mm)``: the name without its unit, then the unit
    :data:`OUTPUTS` declares."""
    unit = OUTPUTS[out][0]
    words = out.split("_")
    tail = unit.replace("/", "_per_").split("_")
    if unit not in ("1",) and words[-len(tail) :] == tail:
        words = words[: -len(tail)]
    text = " ".join(words).replace("mean abs ", "mean |").replace("max abs ", "largest |")
    if "|" in text:
        text += "|"
    return text + _unit_suffix(unit)


@functools.cache
def _declared_axes() -> dict[str, tuple[str, str]]:
    """Design-axis key -> (meaning, unit), from the FE and reduced scenario schemas."""
    from bristlecrawler.scenario.keys import field_meaning, scenario_keys, unit_of
    from bristlecrawler.scenario.reduced import ReducedConfig

    found = {}
    for name, field in ReducedConfig.model_fields.items():
        unit = unit_of(field.description or "")
        found[name] = (field_meaning(field.description or "", unit), unit)
    for k in scenario_keys():
        found.setdefault(k.key, (k.meaning, k.unit))
    return found


def axis_label(key: str) -> str:
    """A design axis's meaning, shortened to its first clause, and unit:
    ``bristle.alpha_deg`` -> ``inclination from the vertical (degrees)``; the key itself
    where the schema does not declare it."""
    meaning, unit = _declared_axes().get(key, ("", ""))
    if not meaning:
        return key
    short = re.split(r"[;(]| - ", meaning)[0].strip().rstrip(",")
    if short[1:2].islower():  # an ordinary word, not a symbol such as F_p
        short = short[:1].lower() + short[1:]
    return short + _unit_suffix(unit)


def fit_title(text: str, width_in: float, fontsize: float = 9) -> str:
    """``text`` wrapped to the width of a figure ``width_in`` inches wide."""
    chars = max(int(width_in * 72 / (0.55 * fontsize)), 20)
    return "\n".join(textwrap.wrap(text, chars))


def _not_done(ds):
    return (ds.status == int(DesignStatus.FAILED)) | (ds.status == int(DesignStatus.LOST))


def _mark_failed(ax, ds, key) -> bool:
    """Red crosses at the foot of ``ax`` at the ``key`` values of the failed or lost
    designs; whether there were any."""
    bad = _not_done(ds)
    if not bool(bad.any()):
        return False
    from bristlecrawler.viz.reproduce import mark_failed

    mark_failed(ax, ds[key].broadcast_like(bad).values.ravel()[bad.values.ravel()])
    return True


def _fmt(v) -> str:
    return f"{v:.4g}" if isinstance(v, float | np.floating) else str(v)


def _numeric(ds, key) -> bool:
    return ds[key].dtype.kind in "iuf"


def _against_axis(ax, ds, out, key) -> None:
    y = ds[out].where(ds.status == int(DesignStatus.DONE))
    others = [d for d in y.dims if d != key]
    lines = int(np.prod([y.sizes[d] for d in others])) if others else 1
    if key in ds.dims and lines <= MAX_LINES:
        stacked = y.stack(_line=others) if others else y.expand_dims(_line=[0])
        for j in range(stacked.sizes["_line"]):
            label = None
            if others:
                idx = stacked["_line"].values[j]
                idx = idx if isinstance(idx, tuple) else (idx,)
                label = ", ".join(f"{d}={_fmt(v)}" for d, v in zip(others, idx, strict=True))
            ax.plot(ds[key].values, stacked.isel(_line=j).values, "o-", ms=3, label=label)
    else:
        x = ds[key].broadcast_like(y).values.ravel()
        v = y.values.ravel()
        if v.size > MAX_POINTS:
            keep = np.random.default_rng(0).choice(v.size, MAX_POINTS, replace=False)
            x, v = x[keep], v[keep]
        ax.plot(x, v, ".", ms=2)
    if _mark_failed(ax, ds, key) or others:
        ax.legend(fontsize=6)
    ax.set_xlabel(axis_label(key))
    ax.set_ylabel(output_label(out))
    ax.grid(alpha=0.3)


def plot_outputs(ds, keys: list[str], folder: Path) -> list[Path]:
    """One figure per output, one panel per numeric axis; returns the files written."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from bristlecrawler.viz.reduced import save_figure

    keys = [k for k in keys if _numeric(ds, k)]
    written = []
    if not keys:
        return written
    width = 4.2 * len(keys)
    for out in PLOTTED:
        fig, axes = plt.subplots(1, len(keys), figsize=(width, 3.6), squeeze=False)
        for ax, key in zip(axes[0], keys, strict=True):
            _against_axis(ax, ds, out, key)
        title = f"{ds.attrs.get('study_name', '')}: {OUTPUTS[out][1]}"
        fig.suptitle(fit_title(title, width), fontsize=9)
        fig.tight_layout()
        path = folder / f"{out}.png"
        save_figure(fig, path)
        written.append(path)
    return written


def plot_maps(ds, keys: list[str], folder: Path) -> list[Path]:
    """Maps of the headline outputs over the first two numeric axes (a colour map on a
    grid, averaged over any other axes; coloured points for sampled or zipped axes)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from bristlecrawler.viz.reduced import save_figure

    keys = [k for k in keys if _numeric(ds, k)]
    if len(keys) < 2:
        return []
    a, b = keys[:2]
    written = []
    for out in MAPPED:
        y = ds[out].where(ds.status == int(DesignStatus.DONE))
        fig, ax = plt.subplots(figsize=(5.2, 4.2))
        if a in ds.dims and b in ds.dims:
            others = [d for d in y.dims if d not in (a, b)]
            m = y.mean(others) if others else y
            mesh = ax.pcolormesh(
                ds[a].values, ds[b].values, m.transpose(b, a).values, shading="nearest"
            )
            if others:
                ax.set_title(f"mean over {', '.join(others)}", fontsize=8)
        else:
            x = ds[a].broadcast_like(y).values.ravel()
            z = ds[b].broadcast_like(y).values.ravel()
            mesh = ax.scatter(x, z, c=y.values.ravel(), s=8)
        bad = _not_done(ds)
        if bool(bad.any()):
            keep = bad.values.ravel()
            ax.plot(
                ds[a].broadcast_like(bad).values.ravel()[keep],
                ds[b].broadcast_like(bad).values.ravel()[keep],
                "x",
                color="tab:red",
                ms=7,
                mew=2,
                label="failed (no value)",
            )
            ax.legend(fontsize=6, loc="upper right")
        fig.colorbar(mesh, ax=ax, label=output_label(out))
        ax.set_xlabel(axis_label(a))
        ax.set_ylabel(axis_label(b))
        fig.tight_layout()
        path = folder / f"map_{out}.png"
        save_figure(fig, path)
        written.append(path)
    return written
