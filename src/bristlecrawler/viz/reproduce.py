"""Figures of the reproduction report that no single command draws."""

from __future__ import annotations

import numpy as np

from bristlecrawler.viz.reduced import pyplot


def plot_vertical(phases, histories, inclined=None):
    """alpha = 0 from several starting places: Delta(s) of each one-cycle run (left) and
    its advance against the starting place (right), beside the advance per cycle of the
    inclined crawler (``inclined``, mm, or None)."""
    plt = pyplot()
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(10.0, 4.2))
    colors = plt.cm.viridis(np.linspace(0.0, 0.9, max(len(histories), 1)))
    for p, h, c in zip(phases, histories, colors, strict=True):
        a1.plot(h.s, h.delta, color=c, lw=1.2, label=f"shift {p:g} mm")
    a1.set_xlabel("shortening s (mm)")
    a1.set_ylabel(r"displacement of the right end $\Delta$ (mm)")
    a1.set_title(r"$\alpha$ = 0: one cycle from each starting place", fontsize=10)
    a1.legend(fontsize=7, loc="best")
    adv = np.array([h.net_advance for h in histories])
    a2.plot(phases, adv, "o", color="k", label=r"$\alpha$ = 0, one cycle each")
    a2.axhline(float(adv.mean()), color="k", lw=1.0, ls="--", label=r"$\alpha$ = 0, mean")
    if inclined:
        a2.axhline(
            float(np.mean(inclined)),
            color="tab:red",
            lw=1.2,
            label=r"$\alpha = \pi/4$, mean per cycle",
        )
    a2.axhline(0.0, color="0.6", lw=0.8)
    a2.set_xlabel("shift of the texture (mm)")
    a2.set_ylabel("advance in the cycle (mm)")
    a2.legend(fontsize=7, loc="best")
    for ax in (a1, a2):
        ax.grid(alpha=0.3)
    fig.tight_layout()
    return fig


def plot_study(values, outputs, axis_label: str, title: str, failed=None, quanta=None):
    """Outputs of a one-axis design study: ``values`` on x, one panel per entry of
    ``outputs`` (label -> array, NaN where a design failed); ``failed`` (booleans, one
    per value) marks the designs that failed with a red cross at the foot of each panel.

    Each panel's axis starts at zero, so that a difference of round-off is not drawn as a
    trend; ``quanta`` (label -> mm) draws the whole multiples of a quantum (the texture's
    pitch, which an FE crawler's cycle advances by) as dotted lines on that panel."""
    import numpy as np

    plt = pyplot()
    fig, axes = plt.subplots(1, len(outputs), figsize=(4.2 * len(outputs), 3.6), squeeze=False)
    bad = np.zeros(len(values), bool) if failed is None else np.asarray(failed, bool)
    quanta = quanta or {}
    for ax, (label, y) in zip(axes[0], outputs.items(), strict=True):
        ax.plot(values, y, "o-", color="k")
        finite = np.asarray(y, float)[np.isfinite(y)]
        high = max(float(finite.max()) if finite.size else 1.0, 0.0)
        low = min(float(finite.min()) if finite.size else 0.0, 0.0)
        ax.set_ylim(low - 0.05 * (high - low + 1e-9), high + 0.08 * (high - low + 1e-9))
        q = quanta.get(label)
        if q:
            for k in range(int(np.floor(low / q)), int(np.ceil(high / q)) + 1):
                ax.axhline(k * q, color="0.6", ls=":", lw=0.8)
            ax.plot([], [], color="0.6", ls=":", lw=0.8, label=f"whole pitches ({q:g} mm)")
        if bad.any():
            mark_failed(ax, np.asarray(values)[bad])
        if ax.get_legend_handles_labels()[0]:
            ax.legend(fontsize=7)
        ax.set_xlabel(axis_label)
        ax.set_ylabel(label)
        ax.grid(alpha=0.3, axis="x")
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    return fig


def mark_failed(ax, x) -> None:
    """Red crosses at the foot of ``ax`` at the abscissae ``x`` of designs that failed
    (they have no value to plot)."""
    ax.plot(
        x,
        np.full(np.size(x), 0.03),
        "x",
        color="tab:red",
        ms=7,
        mew=2,
        transform=ax.get_xaxis_transform(),
        clip_on=False,
        label="failed (no value)",
    )
