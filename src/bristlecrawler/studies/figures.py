"""Figures of a study: each output against each axis, and maps over two axes."""

from __future__ import annotations

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
        if others:
            ax.legend(fontsize=6)
    else:
        x = ds[key].broadcast_like(y).values.ravel()
        v = y.values.ravel()
        if v.size > MAX_POINTS:
            keep = np.random.default_rng(0).choice(v.size, MAX_POINTS, replace=False)
            x, v = x[keep], v[keep]
        ax.plot(x, v, ".", ms=2)
    ax.set_xlabel(key)
    ax.set_ylabel(f"{out}")
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
    for out in PLOTTED:
        fig, axes = plt.subplots(1, len(keys), figsize=(4.2 * len(keys), 3.4), squeeze=False)
        for ax, key in zip(axes[0], keys, strict=True):
            _against_axis(ax, ds, out, key)
        fig.suptitle(f"{ds.attrs.get('study_name', '')}: {OUTPUTS[out][1]}", fontsize=9)
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
        fig.colorbar(mesh, ax=ax, label=f"{out}")
        ax.set_xlabel(a)
        ax.set_ylabel(b)
        fig.tight_layout()
        path = folder / f"map_{out}.png"
        save_figure(fig, path)
        written.append(path)
    return written
