"""A one-axis study's figure does not draw round-off as a trend: its axes start at zero,
and the advance of an FE crawler is drawn against the whole pitches it moves by."""

import matplotlib
import numpy as np

matplotlib.use("Agg")

from bristlecrawler.viz.reproduce import plot_study


def test_a_study_of_values_close_together_is_drawn_from_zero_with_whole_pitches():
    alpha = np.array([15.0, 30.0, 45.0, 60.0])
    advance = np.array([16.2, 16.9, 17.6, 16.4])  # within one 2 mm pitch
    work = np.array([30.1, 30.4, 30.2, 30.3])
    outputs = {"advance (mm)": advance, "work (mJ)": work}
    fig = plot_study(alpha, outputs, "alpha (degrees)", "t", quanta={"advance (mm)": 2.0})
    adv_ax, work_ax = fig.axes
    for ax, y in ((adv_ax, advance), (work_ax, work)):
        low, high = ax.get_ylim()
        assert low <= 0.0 and high >= y.max()
    dotted = [ln for ln in adv_ax.get_lines() if ln.get_linestyle() == ":"]
    whole = sorted({round(float(ln.get_ydata()[0]), 9) for ln in dotted if len(ln.get_ydata())})
    assert whole[:2] == [0.0, 2.0] and whole[-1] >= 18.0
    assert "whole pitches (2 mm)" in [t.get_text() for t in adv_ax.get_legend().get_texts()]
    assert work_ax.get_legend() is None  # nothing to explain there
