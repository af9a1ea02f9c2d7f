"""A figure of your own from a finite-element run: the tips' paths over the texture.

Each bristle tip's height against its horizontal position, coloured by its contact state
(stick, slip, open), over the substrate's profile: where a tip holds, where it slides,
whether it drops into a groove. ``bristlecrawler simulate`` draws the standard figures
(``delta_vs_s.png``, ``shapes.png``, ``connector.png``); this one is built from the
dataset with matplotlib alone. Run on a ``crawler.nc`` of your own::

    python examples/fe_custom_figure.py runs/<id>/crawler.nc tips.png

Without arguments it makes a short run (the inclined one of ``fe_run_scenario.py``) and
draws it into a temporary folder.
"""

from __future__ import annotations

import sys
import tempfile
from pathlib import Path

import xarray as xr

STATE_COLOURS = {0: ("open", "0.6"), 1: ("stick", "tab:blue"), 2: ("slip", "tab:red")}


def tip_figure(ds: xr.Dataset):
    """Figure: tip height against tip x for both bristles, dots coloured by contact state."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(9, 3), constrained_layout=True)
    tips, states = ds["tip_position"].values, ds["tip_state"].values
    sub = ds["substrate_xy"].values
    names = ("left (rear) tip", "right (front) tip")
    for b, (ax, name) in enumerate(zip(axes, names, strict=True)):
        x, y = tips[:, b, 0], tips[:, b, 1]
        pad = 1.0
        keep = (sub[:, 0] > x.min() - pad) & (sub[:, 0] < x.max() + pad)
        ax.plot(sub[keep, 0], sub[keep, 1], color="k", lw=1)
        for code, (label, colour) in STATE_COLOURS.items():
            m = states[:, b] == code
            if m.any():
                ax.scatter(x[m], y[m], s=6, color=colour, label=label)
        ax.set_title(name)
        ax.set_xlabel("x (mm)")
        ax.set_ylabel("y (mm)")
        ax.legend(loc="best", fontsize=7)
    return fig


def numbers(ds: xr.Dataset) -> dict[str, float]:
    """How far each tip travelled (mm) and the lowest it went (mm, land level 0)."""
    tips = ds["tip_position"].values
    return {
        "left_tip_travel_mm": float(tips[-1, 0, 0] - tips[0, 0, 0]),
        "right_tip_travel_mm": float(tips[-1, 1, 0] - tips[0, 1, 0]),
        "lowest_tip_y_mm": float(tips[:, :, 1].min()),
    }


QUICK = [
    "actuation.s_max=8.0",  # mm
    "actuation.period=4.0",  # s
    "actuation.cycles=1",
]


def quick_dataset() -> xr.Dataset:
    """A short run of ``paper`` as the dataset ``crawler.nc`` would hold."""
    from bristlecrawler.crawler import run
    from bristlecrawler.fe import enable_compilation_cache
    from bristlecrawler.scenario import load_spec

    enable_compilation_cache()
    return run(load_spec("paper", QUICK)).to_dataset()


def make(ds: xr.Dataset, figure: Path) -> dict[str, float]:
    """Write the figure to ``figure``; return the tips' numbers."""
    import matplotlib.pyplot as plt

    fig = tip_figure(ds)
    fig.savefig(figure, dpi=120)
    plt.close(fig)
    return numbers(ds)


if len(sys.argv) > 1 and __name__ == "__main__":
    figure_path = Path(sys.argv[2] if len(sys.argv) > 2 else "tip_paths.png")
    with xr.open_dataset(sys.argv[1]) as dataset:
        result = make(dataset, figure_path)
else:
    figure_path = Path(tempfile.mkdtemp()) / "tip_paths.png"
    result = make(quick_dataset(), figure_path)


def main() -> None:
    for key, value in result.items():
        print(f"{key:22s} {value:+.4f}")
    print(f"figure: {figure_path}")


if __name__ == "__main__":
    main()
