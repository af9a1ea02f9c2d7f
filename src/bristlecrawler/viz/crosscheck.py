"""Figure of a cross-check: two FE codes' drag tests, force against carriage travel."""

from __future__ import annotations

from bristlecrawler.viz.reduced import pyplot


def plot_crosscheck(legs: dict, labels: tuple[str, str], title: str = ""):
    """One panel per leg: force (N) against carriage travel (mm) of both codes; ``legs``
    maps a leg's name to its two series, each (x, force)."""
    plt = pyplot()
    fig, axes = plt.subplots(1, len(legs), figsize=(5.0 * len(legs), 3.8), squeeze=False)
    styles = ({"color": "tab:blue"}, {"color": "tab:red", "ls": "--"})
    for ax, (leg, pair) in zip(axes[0], legs.items(), strict=True):
        for (x, f), label, style in zip(pair, labels, styles, strict=True):
            ax.plot(x, f, lw=1.4, label=label, **style)
        ax.axhline(0.0, color="0.7", lw=0.8)
        ax.set_title(f"on a {leg}" if leg == "flat" else f"from a {leg}'s middle", fontsize=10)
        ax.set_xlabel("carriage travel (mm)")
        ax.set_ylabel("horizontal force on the bristle (N)")
        ax.legend(loc="best", fontsize=8)
    if title:
        fig.suptitle(title, fontsize=11)
    fig.tight_layout()
    return fig
