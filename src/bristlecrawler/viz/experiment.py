"""Figure of a recorded gait with the fitted reduced model overlaid (paper Fig. 3 style)."""

from __future__ import annotations

import numpy as np

from bristlecrawler.viz.reduced import SLIP_STYLE, STICK_STYLE, pyplot


def plot_analysis(analysis, title: str | None = None):
    """Delta versus s: measurement (grey), fitted loop per cycle (stick blue-dashed, slip
    red-solid), detected transitions (black dots). Returns the Figure."""
    from bristlecrawler.experiment.fit import loop_shape
    from bristlecrawler.reduced import closed_form as cf

    plt = pyplot()
    sig, fit = analysis.signals, analysis.fit
    fig, ax = plt.subplots(figsize=(6.8, 5.0))
    i0, i1 = sig.cycles[0, 0], sig.cycles[-1, 2]
    ax.plot(
        sig.s[i0 : i1 + 1], sig.delta[i0 : i1 + 1], color="k", lw=3.0, alpha=0.25, label="measured"
    )
    c = fit.fp_over_k_mm
    labelled = set()
    for n, (a, _, _) in enumerate(sig.cycles):
        if not np.isfinite(c):
            break
        S = float(fit.s_max_mm[n])
        first = n == 0 and fit.first_cycle_unloaded
        s_up = np.linspace(0, S, 200)
        s_dn = s_up[::-1]
        s = np.concatenate([s_up, s_dn])
        up = np.concatenate([np.ones(200, bool), np.zeros(200, bool)])
        d = sig.delta[a] + fit.offsets_mm[n] + loop_shape(s, up, S, c, first)
        state = cf.trajectory(s, 1 if first else 2, up, S, c, 1.0).state.any(axis=1)
        cuts = np.flatnonzero(np.diff(state.astype(int))) + 1
        for lo, hi in zip(np.r_[0, cuts], np.r_[cuts, s.size], strict=True):
            slip = bool(state[min(lo + 1, hi - 1)])
            style = SLIP_STYLE if slip else STICK_STYLE
            name = ("model: slip" if slip else "model: stick") if slip not in labelled else None
            labelled.add(slip)
            ax.plot(
                s[max(lo - 1, 0) : hi],
                d[max(lo - 1, 0) : hi],
                label=name,
                **(style | {"linewidth": 1.1}),
            )
    for tr in analysis.transitions:
        k = int(np.argmin(np.abs(sig.t - tr.t)))
        ax.plot(
            tr.s,
            sig.delta[k],
            "o",
            color="k",
            ms=3.5,
            label="detected transition" if tr is analysis.transitions[0] else None,
        )
    ax.set_xlabel("shortening s (mm)")
    ax.set_ylabel(r"displacement of the front end $\Delta$ (mm)")
    ax.grid(alpha=0.3)
    ax.legend(loc="upper left", fontsize=8)
    ax.set_title(
        title
        or f"{analysis.signals.n_cycles} cycles, net {analysis.net_advance:.1f} mm, "
        f"F_p/k = {c:.3f} mm"
    )
    return fig
