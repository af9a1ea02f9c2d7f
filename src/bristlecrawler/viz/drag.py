"""Figure of a drag test: the carriage's force against its travel, sliding means marked."""

from __future__ import annotations

import numpy as np

from bristlecrawler.results import keys
from bristlecrawler.viz.reduced import SLIP_STYLE, STICK_STYLE, pyplot


def plot_drag(r, title: str = ""):
    """Force (N) against carriage travel (mm); stick blue-dashed, slip red, tip off the
    substrate grey; the sliding means F_p and -F_n as horizontal lines, the first
    loading's secant k (from the start to F_p) as a dotted line."""
    from bristlecrawler.states import ContactState

    plt = pyplot()
    fig, ax = plt.subplots(figsize=(7.0, 4.0))
    kinds = (
        (ContactState.STICK, STICK_STYLE, "stick"),
        (ContactState.SLIP, SLIP_STYLE, "slip"),
        (ContactState.OPEN, {"color": "0.6", "lw": 1.0}, "tip off the substrate"),
    )
    for state, style, label in kinds:
        mask = r.tip_state == state
        if mask.any():
            ax.plot(r.x, np.where(mask, r.force_x, np.nan), label=label, **style)
    s = r.summary()
    if np.isfinite(s[keys.FP_N]):
        ax.axhline(s[keys.FP_N], color="tab:green", lw=1.0, label=f"F_p = {s[keys.FP_N]:.3f} N")
    if np.isfinite(s[keys.FN_N]):
        ax.axhline(-s[keys.FN_N], color="tab:purple", lw=1.0, label=f"-F_n = {-s[keys.FN_N]:.3f} N")
    k = s[keys.K_N_PER_MM]
    if np.isfinite(k):
        d = r.legs[0][2]
        target = d * (s[keys.FP_N] if d > 0 else s[keys.FN_N])
        xs = r.x[0] + d * np.array([0.0, abs(target - r.force_x[0]) / k])
        ax.plot(xs, [r.force_x[0], target], "k:", lw=1.2, label=f"k = {k:.3f} N/mm")
    ax.set_xlabel("carriage travel (mm)")
    ax.set_ylabel("horizontal force on the bristle (N)")
    ax.legend(loc="best", fontsize=8)
    if title:
        ax.set_title(title)
    fig.tight_layout()
    return fig


def plot_texture(law, samples=None, title: str = ""):
    """A texture law over one pitch: F_p(x) (along the grain) above the axis and -F_n(x)
    (against it) below, as steps over the cells (N against the position within the pitch,
    mm); walls and lock positions as vertical lines. ``samples``: optional (position mm,
    force N) of a drag test's reduced tip, shown mod the pitch as dots."""
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(7.0, 4.0))
    edges = np.arange(law.n_cells + 1) * law.cell_mm
    fp = np.append(law.fp_N, law.fp_N[-1])
    fn = np.where(np.isfinite(law.fn_N), law.fn_N, np.nan)
    fn = np.append(fn, fn[-1])
    if samples is not None:
        x, f = samples
        ax.plot((x - law.origin_mm) % law.pitch_mm, f, ".", ms=2, color="0.7", label="drag test")
    ax.step(edges, fp, where="post", color="tab:green", lw=1.5, label="F_p(x), along")
    ax.step(edges, -fn, where="post", color="tab:purple", lw=1.5, label="-F_n(x), against")
    locks = np.concatenate([law.lock_positions_mm, law.lock_positions_mm + law.pitch_mm])
    for j, x in enumerate(locks):
        ax.axvline(x, color="k", ls=":", lw=1.5, label="lock (wall)" if j == 0 else None)
    ax.axhline(0.0, color="0.5", lw=0.5)
    ax.set_xlim(0.0, law.pitch_mm)
    ax.set_xlabel(f"tip position within a pitch (mm from {law.origin_mm:g} mm)")
    ax.set_ylabel("resistance of the substrate (N)")
    ax.set_title(title or f"texture law, k = {law.k_N_per_mm:.3f} N/mm")
    ax.legend(loc="best", fontsize=8)
    fig.tight_layout()
    return fig
