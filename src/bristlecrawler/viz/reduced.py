"""Figures of the reduced model, styled like the paper's Figs. 8 and 10.

Stick (every tip at rest) is drawn blue-dashed, slip (some tip sliding) red-solid, as in the
paper's one-dimensional-model figure.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from bristlecrawler.io.atomic import atomic_path

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from bristlecrawler.reduced.friction import DirectionalFriction
    from bristlecrawler.reduced.solver import ReducedResult

STICK_STYLE = {"color": "tab:blue", "linestyle": "--", "linewidth": 1.4}
SLIP_STYLE = {"color": "tab:red", "linestyle": "-", "linewidth": 1.8}


def pyplot():
    """matplotlib.pyplot, imported on first use, on the Agg backend unless MPLBACKEND says
    otherwise (figures are written to files)."""
    import matplotlib

    if not os.environ.get("MPLBACKEND"):
        matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def save_figure(fig: Figure, path: str | os.PathLike, dpi: int = 150) -> Path:
    """Save atomically and close the figure."""
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=dpi, bbox_inches="tight", format=Path(path).suffix.lstrip("."))
    pyplot().close(fig)
    return Path(path)


def plot_delta_vs_s(result: ReducedResult, ax: Axes | None = None, title: str | None = None):
    """Delta (front-end displacement) versus body shortening, stick/slip coloured.

    Returns the matplotlib Figure.
    """
    plt = pyplot()
    if ax is None:
        fig, ax = plt.subplots(figsize=(6.4, 4.8))
    else:
        fig = ax.figure
    s = result.shortening.sum(axis=1)
    d = result.delta
    sliding = np.any(result.state != 0, axis=1)
    # The state of sample j belongs to the interval (j-1, j): colour segments accordingly.
    change = np.flatnonzero(np.diff(sliding[1:].astype(int))) + 1
    starts = np.concatenate([[0], change])
    ends = np.concatenate([change, [s.size - 1]])
    labelled = set()
    for a, b in zip(starts, ends, strict=True):
        slip = bool(sliding[a + 1])
        style = SLIP_STYLE if slip else STICK_STYLE
        label = ("slip" if slip else "stick") if slip not in labelled else None
        labelled.add(slip)
        ax.plot(s[a : b + 1], d[a : b + 1], label=label, **style)
    ax.set_xlabel("shortening s (mm)")
    ax.set_ylabel(r"displacement of the front end $\Delta$ (mm)")
    ax.set_xlim(left=0)
    ax.grid(alpha=0.3)
    ax.legend(loc="upper left")
    if title:
        ax.set_title(title)
    return fig


def plot_friction_law(law: DirectionalFriction, ax: Axes | None = None, vmax: float = 1.0):
    """The set-valued force-velocity law of eq. (4.1), as in the paper's Fig. 8."""
    plt = pyplot()
    if ax is None:
        fig, ax = plt.subplots(figsize=(5.0, 4.0))
    else:
        fig = ax.figure
    ax.plot([-vmax, 0.0], [law.fn, law.fn], color="k", lw=2)
    ax.plot([0.0, 0.0], [-law.fp, law.fn], color="k", lw=2)
    ax.plot([0.0, vmax], [-law.fp, -law.fp], color="k", lw=2)
    ax.axhline(0.0, color="0.6", lw=0.8)
    ax.axvline(0.0, color="0.6", lw=0.8)
    ax.annotate(
        rf"$F_n$ = {law.fn:.3g} N",
        (-0.95 * vmax, law.fn),
        xytext=(0, -14),
        textcoords="offset points",
    )
    ax.annotate(
        rf"$-F_p$ = {-law.fp:.3g} N",
        (0.3 * vmax, -law.fp),
        xytext=(0, 6),
        textcoords="offset points",
    )
    span = law.fn + law.fp
    ax.set_ylim(-law.fp - 0.15 * span, law.fn + 0.15 * span)
    ax.set_xlabel(r"tip sliding velocity $\dot x_i$ (arbitrary scale)")
    ax.set_ylabel(r"force on the crawler $F_i$ (N)")
    ax.set_title("directional friction law")
    ax.set_xticks([])
    return fig
