"""Figure of a cross-check: two FE codes' drag tests, force against carriage travel."""

from __future__ import annotations

from bristlecrawler.viz.reduced import pyplot


def plot_crosscheck(first, second, labels: tuple[str, str], title: str = ""):
    """Force (N) against carriage travel (mm) of two drag tests, each (x, force)."""
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(7.0, 4.0))
    for (x, f), label, style in zip(
        (first, second),
        labels,
        ({"color": "tab:blue"}, {"color": "tab:red", "ls": "--"}),
        strict=True,
    ):
        ax.plot(x, f, lw=1.4, label=label, **style)
    ax.axhline(0.0, color="0.7", lw=0.8)
    ax.set_xlabel("carriage travel (mm)")
    ax.set_ylabel("horizontal force on the bristle (N)")
    ax.legend(loc="best", fontsize=8)
    if title:
        ax.set_title(title)
    fig.tight_layout()
    return fig
