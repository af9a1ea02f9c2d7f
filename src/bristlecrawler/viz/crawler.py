"""Figures of finite-element crawler runs, like the paper's Figs. 4, 5 and 6."""

from __future__ import annotations

import numpy as np

from bristlecrawler.viz.reduced import SLIP_STYLE, STICK_STYLE, pyplot


def plot_delta_vs_s(h, title: str | None = None):
    """Delta versus s over all cycles; slip (some tip sliding) red, stick blue-dashed."""
    from bristlecrawler.crawler.history import TIP_SLIP

    plt = pyplot()
    fig, ax = plt.subplots(figsize=(6.4, 4.8))
    sliding = np.any(h.tip_state == TIP_SLIP, axis=1)
    cuts = np.flatnonzero(np.diff(sliding.astype(int))) + 1
    labelled = set()
    for a, b in zip(np.r_[0, cuts], np.r_[cuts, h.t.size], strict=True):
        slip = bool(sliding[a])
        name = ("slip" if slip else "stick") if slip not in labelled else None
        labelled.add(slip)
        lo = max(a - 1, 0)
        ax.plot(h.s[lo:b], h.delta[lo:b], label=name, **(SLIP_STYLE if slip else STICK_STYLE))
    ax.set_xlabel("shortening s (mm)")
    ax.set_ylabel(r"displacement of the right end $\Delta$ (mm)")
    ax.grid(alpha=0.3)
    ax.legend(loc="upper left")
    ax.set_title(title or f"net advance {h.net_advance:.2f} mm")
    return fig


def plot_connector(h):
    """F_c(t) and W_c(t) with the first cycle shaded grey (paper Fig. 6)."""
    plt = pyplot()
    fig, (a1, a2) = plt.subplots(2, 1, figsize=(7.0, 5.2), sharex=True)
    a1.plot(h.t, h.connector_force, color="k", lw=0.8)
    a1.set_ylabel(r"connector force $F_c$ (N)")
    a2.plot(h.t, h.connector_work, color="k", lw=1.2)
    a2.set_ylabel(r"connector work $W_c$ (mJ)")
    a2.set_xlabel("time t (s)")
    if h.period is not None:
        for ax in (a1, a2):
            ax.axvspan(h.t[0], h.t[0] + h.period, color="0.85", zorder=0, label="first cycle")
        a1.legend(loc="upper right", fontsize=8)
    for ax in (a1, a2):
        ax.grid(alpha=0.3)
    return fig


def draw_frame(
    ax,
    h,
    f: int,
    xlim: tuple[float, float] | None = None,
    ylim: tuple[float, float] | None = None,
    axes: bool = False,
    bar: float | None = None,
    chains: list[np.ndarray] | None = None,
) -> None:
    """Draw frame ``f``: body black, links grey, bristles red, substrate grey; ``axes``
    keeps the axes with their mm ticks (zoomed views), else a scale bar ``bar`` mm long
    is drawn below the substrate at the left. ``chains``: ``h.bristle_chains()``, passed
    by callers that draw many frames so that it is found once."""
    nodes = h.frame_nodes[f]
    colors = {0: "k", 1: "0.3", 2: "tab:red"}
    widths = {0: 2.5, 1: 1.5, 2: 1.2}
    for kind in (0, 1, 2):
        segs = h.lines[h.line_kind == kind]
        for a, b in segs:
            ax.plot(nodes[[a, b], 0], nodes[[a, b], 1], color=colors[kind], lw=widths[kind])
    if h.node_thickness is not None:
        for chain in h.bristle_chains() if chains is None else chains:
            ax.fill(
                *_outline(nodes[chain], h.node_thickness[chain]).T,
                color="tab:red",
                alpha=0.35,
                lw=0,
            )
    sub = h.substrate_xy
    ax.fill_between(sub[:, 0], sub[:, 1], sub[:, 1].min() - 2.0, color="0.85", lw=0)
    ax.plot(sub[:, 0], sub[:, 1], color="0.4", lw=0.6)
    ax.set_aspect("equal")
    if xlim is not None:
        ax.set_xlim(*xlim)
    if ylim is not None:
        ax.set_ylim(*ylim)
    if axes:
        ax.tick_params(labelsize=6, length=2, pad=1)
        return
    ax.set_axis_off()
    if bar is not None:
        x0 = (xlim or (float(nodes[:, 0].min()), 0.0))[0] + 1.0
        y0 = float(sub[:, 1].min()) - 1.5
        ax.plot([x0, x0 + bar], [y0, y0], color="k", lw=1.5)
        ax.text(x0 + 0.5 * bar, y0 - 0.5, f"{bar:g} mm", fontsize=6, ha="center", va="top")


def _frame_at(h, t: float) -> int:
    return int(np.argmin(np.abs(h.frame_t - t)))


def _outline(x: np.ndarray, thickness: np.ndarray) -> np.ndarray:
    """Closed outline (2n, 2) of a beam drawn from its axis points ``x`` (n, 2) and
    thicknesses (n,), mm: the faces h/2 either side along the normal of the axis."""
    t = np.gradient(x, axis=0)
    t /= np.linalg.norm(t, axis=1, keepdims=True)
    n = np.stack([-t[:, 1], t[:, 0]], axis=1) * (0.5 * thickness)[:, None]
    return np.concatenate([x + n, (x - n)[::-1]])


def plot_shapes(h, zoom: float = 4.5, max_rows: int = 10):
    """Deformed shapes at the start, full contraction and re-extension of each cycle (paper
    Fig. 5): the whole crawler with dashed verticals at its ends' positions and a 10 mm
    bar, and below it each bristle in a window ``zoom`` mm either side of its middle, with
    the grooves and mm axes."""
    plt = pyplot()
    # Without a period (a recorded or SMA history) the run is drawn as one stroke; of
    # many cycles, at most ``max_rows`` evenly spaced ones (first and last included).
    n_cycles = max(h.cycles, 1) if h.period is not None else 1
    period = h.period or (h.t[-1] - h.t[0])
    rows = np.unique(np.linspace(0, n_cycles - 1, min(n_cycles, max_rows)).round().astype(int))
    n = rows.size
    # Sized for the report's 860 px column: 8 pt ticks stay legible once scaled down, and
    # the whole crawler's strip gets the height its 1:1 drawing fills (no blank band).
    fig = plt.figure(figsize=(8.6, 2.0 * n + 0.5))
    outer = fig.add_gridspec(n, 3, hspace=0.35, wspace=0.2)
    xs = h.frame_nodes[..., 0]
    xlim = (float(xs.min()) - 3.0, float(xs.max()) + 3.0)
    bristles = h.bristle_chains()
    y_sub = h.substrate_xy[:, 1]
    labels = ("start", "contracted", "re-extended")
    for r, c in enumerate(rows):
        t0 = h.t[0] + c * period
        times = (t0, t0 + 0.5 * period, t0 + period)
        if h.period is None:  # the fullest contraction of the whole history
            times = (h.t[0], float(h.t[np.argmax(h.s)]), h.t[-1])
        for j, t in enumerate(times):
            cell = outer[r, j].subgridspec(
                2, max(len(bristles), 1), height_ratios=(0.45, 1.0), hspace=0.25
            )
            ax = fig.add_subplot(cell[0, :])
            f = _frame_at(h, t)
            draw_frame(ax, h, f, xlim, bar=10.0, chains=bristles)
            for text in ax.texts:
                text.set_fontsize(8)
            m = int(np.argmin(np.abs(h.t - h.frame_t[f])))
            for x in (h.left[m, 0], h.right[m, 0]):
                ax.axvline(x, color="tab:blue", ls="--", lw=0.8)
            title = f"{labels[j]}, t = {h.frame_t[f]:.1f} s"
            ax.set_title(f"cycle {c + 1}: {title}" if j == 0 else title, fontsize=9)
            nodes = h.frame_nodes[f]
            for k, ix in enumerate(bristles):
                zx = float(nodes[ix, 0].mean())
                half = 0.0 if h.node_thickness is None else 0.5 * h.node_thickness[ix].max()
                top = float(nodes[ix, 1].max()) + half
                zax = fig.add_subplot(cell[1, k])
                ylim = (float(y_sub.min()) - 0.4, top + 0.4)
                draw_frame(zax, h, f, (zx - zoom, zx + zoom), ylim, axes=True, chains=bristles)
                _legible(zax)
                zax.set_xlabel("x (mm)", fontsize=8, labelpad=1)
                if k == 0:
                    zax.set_ylabel("y (mm)", fontsize=8, labelpad=1)
    fig.suptitle(
        "deformed shapes (body black, links grey, bristles red: axis and section; "
        "dashed: the ends' positions)",
        fontsize=9,
    )
    return fig


def _legible(ax) -> None:
    """Ticks of a small zoomed panel at a size the report shows: 8 pt, few of them."""
    from matplotlib.ticker import MaxNLocator

    ax.tick_params(labelsize=8, length=2, pad=1)
    ax.xaxis.set_major_locator(MaxNLocator(3))
    ax.yaxis.set_major_locator(MaxNLocator(3, integer=True))


def animate(h, path_stem, fps: float = 12.0):
    """GIF (and MP4 when available) of all frames."""
    from bristlecrawler.viz.animation import write_animation

    xs = h.frame_nodes[..., 0]
    xlim = (float(xs.min()) - 3.0, float(xs.max()) + 3.0)
    chains = h.bristle_chains()

    def draw(ax, f):
        draw_frame(ax, h, f, xlim, bar=10.0, chains=chains)
        ax.set_title(f"t = {h.frame_t[f]:.1f} s", fontsize=9)

    return write_animation(draw, h.frame_t.size, path_stem, fps=fps, figsize=(9.0, 2.2))
