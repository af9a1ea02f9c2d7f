"""Figures (matplotlib, imported lazily by the functions that need it)."""

from bristlecrawler.viz.reduced import plot_delta_vs_s, plot_friction_law, save_figure

__all__ = ["plot_delta_vs_s", "plot_friction_law", "save_figure"]
