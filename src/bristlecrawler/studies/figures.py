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

from bristlecrawler.results import keys as result_keys
from bristlecrawler.studies.evaluate import OUTPUTS, DesignStatus

PLOTTED = (
    result_keys.NET_ADVANCE_MM,
    result_keys.ADVANCE_PER_CYCLE_MM,
    result_keys.WORK_MJ,
    result_keys.COST_OF_TRANSPORT,
    "mean_abs_connector_force_N",
    result_keys.MAX_ABS_CONNECTOR_FORCE_N,
)
MAPPED = (result_keys.ADVANCE_PER_CYCLE_MM, result_keys.COST_OF_TRANSPORT)
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


def _value_label(key: str, value) -> str:
    """``fp = 0.05 N``: a design axis's value with its declared unit."""
    unit = _declared_axes().get(key, ("", ""))[1]
    unit = "" if unit in ("", "1", "-") else f" {unit}"
    text = f"{value:.3g}" if isinstance(value, float | np.floating) else str(value)
    return f"{key.split('.')[-1]} = {text}{unit}"


def _evenly(n: int, most: int) -> np.ndarray:
    """At most ``most`` indices of ``range(n)``, evenly spread, the ends included."""
    return np.unique(np.linspace(0, n - 1, min(n, most)).round().astype(int))


def _against_axis(ax, ds, out, key) -> None:
    """``out`` against the axis ``key``: a line per value of the other axes on a grid (a
    few of them, evenly spread, where there are many), else the designs as points."""
    y = ds[out].where(ds.status == int(DesignStatus.DONE))
    others = [d for d in y.dims if d != key]
    lines = int(np.prod([y.sizes[d] for d in others])) if others else 1
    if key in ds.dims:
        stacked = y.stack(_line=others) if others else y.expand_dims(_line=[0])
        picks = _evenly(lines, MAX_LINES)
        for j in picks:
            label = None
            if others:
                idx = stacked["_line"].values[j]
                idx = idx if isinstance(idx, tuple) else (idx,)
                label = ", ".join(_value_label(d, v) for d, v in zip(others, idx, strict=True))
            ax.plot(ds[key].values, stacked.isel(_line=j).values, "-", lw=1.2, label=label)
        if picks.size < lines:
            ax.set_title(f"{picks.size} of {lines} values of {', '.join(others)}", fontsize=8)
    else:
        x = ds[key].broadcast_like(y).values.ravel()
        v = y.values.ravel()
        if v.size > MAX_POINTS:
            keep = np.random.default_rng(0).choice(v.size, MAX_POINTS, replace=False)
            x, v = x[keep], v[keep]
        ax.plot(x, v, ".", ms=2)
    _mark_failed(ax, ds, key)
    if ax.get_legend_handles_labels()[0]:  # an empty legend box says nothing
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
    """Design maps of the headline outputs over the first two numeric axes: on a grid a
    colour map with labelled contours (averaged over any other axes), else coloured
    points; failed designs marked. Returns the files written."""
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
        fig, ax = plt.subplots(figsize=(5.6, 4.4))
        mesh, note, handles = _map(ax, ds, out, a, b)
        _mark_failed_designs(ax, ds, a, b)
        handles += ax.get_legend_handles_labels()[0]
        if handles:
            ax.legend(handles=handles, fontsize=6, loc="upper right")
        fig.colorbar(mesh, ax=ax, label=output_label(out))
        ax.set_xlabel(axis_label(a))
        ax.set_ylabel(axis_label(b))
        title = f"{ds.attrs.get('study_name', '')}: {OUTPUTS[out][1]}{note}"
        ax.set_title(fit_title(title, 4.4), fontsize=9)
        fig.tight_layout()
        path = folder / f"map_{out}.png"
        save_figure(fig, path)
        written.append(path)
    return written


def _map(ax, ds, out: str, a: str, b: str):
    """Draw ``out`` over the axes ``a`` (x) and ``b`` (y); the colour mapping, a note
    for the title and the legend's handles for what is not coloured."""
    y = ds[out].where(ds.status == int(DesignStatus.DONE))
    handles = []
    if not (a in ds.dims and b in ds.dims):
        x = ds[a].broadcast_like(y).values.ravel()
        z = ds[b].broadcast_like(y).values.ravel()
        return ax.scatter(x, z, c=y.values.ravel(), s=8), "", handles
    others = [d for d in y.dims if d not in (a, b)]
    m = (y.mean(others) if others else y).transpose(b, a).values
    xa, xb = ds[a].values, ds[b].values
    mesh = ax.pcolormesh(xa, xb, m, shading="nearest")
    done = (ds.status == int(DesignStatus.DONE)).any([d for d in ds.status.dims if d not in (a, b)])
    if bool((np.isnan(m) & done.transpose(b, a).values).any()):
        from matplotlib.patches import Patch

        # Designs that ran but have no value (the title's output says when): grey.
        ax.set_facecolor("0.8")
        handles.append(Patch(color="0.8", label="no value"))
    if min(m.shape) >= 3 and np.isfinite(m).sum() >= 4:
        from matplotlib.ticker import MaxNLocator

        low, high = np.nanmin(m), np.nanmax(m)
        # Not at the lowest value: a plateau there (no advance) gives a ragged line.
        levels = [v for v in MaxNLocator(8).tick_values(low, high) if low < v < high]
        if levels:
            lines = ax.contour(xa, xb, m, levels=levels, colors="white", linewidths=0.7)
            ax.clabel(lines, fontsize=7, fmt="%.3g")
    return mesh, (f" (mean over {', '.join(others)})" if others else ""), handles


def _mark_failed_designs(ax, ds, a: str, b: str) -> None:
    bad = _not_done(ds)
    if not bool(bad.any()):
        return
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
