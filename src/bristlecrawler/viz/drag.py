"""Figure of a drag test: the carriage's force against its travel, sliding means marked."""

from __future__ import annotations

import numpy as np

from bristlecrawler.viz.reduced import SLIP_STYLE, STICK_STYLE, _pyplot


def plot_drag(r, title: str = ""):
    """Force (N) against carriage travel (mm); stick blue-dashed, slip red; the sliding
    means F_p and -F_n as horizontal lines, the first-loading slope k as a dotted line."""
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(7.0, 4.0))
    slip = r.tip_state == 2
    for mask, style, label in ((~slip, STICK_STYLE, "stick"), (slip, SLIP_STYLE, "slip")):
        x = np.where(mask, r.x, np.nan)
        ax.plot(x, np.where(mask, r.force_x, np.nan), label=label, **style)
    s = r.summary()
    if np.isfinite(s["fp_N"]):
        ax.axhline(s["fp_N"], color="tab:green", lw=1.0, label=f"F_p = {s['fp_N']:.3f} N")
    if np.isfinite(s["fn_N"]):
        ax.axhline(-s["fn_N"], color="tab:purple", lw=1.0, label=f"-F_n = {-s['fn_N']:.3f} N")
    k = s["k_N_per_mm"]
    if np.isfinite(k):
        reach = 0.5 * s["fp_N"] / k if np.isfinite(s["fp_N"]) else 0.5
        xs = np.array([0.0, reach])
        ax.plot(xs, r.force_x[0] + k * xs, "k:", lw=1.2, label=f"k = {k:.3f} N/mm")
    ax.set_xlabel("carriage travel (mm)")
    ax.set_ylabel("horizontal force on the bristle (N)")
    ax.legend(loc="best", fontsize=8)
    if title:
        ax.set_title(title)
    fig.tight_layout()
    return fig
