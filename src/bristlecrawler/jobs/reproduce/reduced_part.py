"""The reduced model (paper Section 4, Figs. 8, 9, 10) and its calibration, twice: from
the paper's numbers (82 mm and 75 mJ over five cycles) and from our own FE run."""

from __future__ import annotations

from bristlecrawler.jobs.reproduce.parts import Context, Figure, Part, PartResult
from bristlecrawler.results import keys

#: The paper's stroke (mm), cycles, advance (mm) and FE work (mJ) that fix F_p/k, F_p, k.
S_MAX_MM, CYCLES, ADVANCE_MM, WORK_MJ = 20.0, 5, 82.0, 75.0


def run_reduced(ctx: Context) -> PartResult:
    from bristlecrawler.reduced import ReducedCrawler, Sin2Stroke, calibrate, simulate
    from bristlecrawler.results.metrics import RunMetrics
    from bristlecrawler.viz.reduced import plot_delta_vs_s, plot_friction_law, save_figure

    cal = calibrate(S_MAX_MM, CYCLES, ADVANCE_MM, WORK_MJ)
    crawler = ReducedCrawler.two_bristle(k=cal.k_N_per_mm, fp=cal.fp_N)
    res = simulate(crawler, Sin2Stroke(S_MAX_MM, 20.0), cycles=CYCLES)
    metrics = RunMetrics.from_reduced(res)
    figs = (
        Figure(
            "reduced-friction-law.png", "The directional friction law, eq. (4.1): paper Fig. 8."
        ),
        Figure(
            "reduced-delta-vs-s.png",
            "Delta(s) of the reduced model over five cycles, "
            "stick dashed, slip solid: paper Figs. 9 and 10.",
        ),
    )
    save_figure(plot_friction_law(crawler.friction(0)), ctx.folder / figs[0].path)
    title = f"reduced model: F_p/k = {cal.fp_over_k_mm:.3f} mm, net {res.net_advance:.2f} mm"
    save_figure(plot_delta_vs_s(res, title=title), ctx.folder / figs[1].path)
    ours = _from_fe(ctx)
    lines = [
        "Calibrated from the paper's numbers (s~ = 20 mm, five cycles, 82 mm, 75 mJ; "
        "`bristlecrawler calibrate --s-max 20 --cycles 5 --advance 82 --work 75`):",
        "",
        f"* F_p/k = **{cal.fp_over_k_mm:.3f} mm**, F_p = **{cal.fp_N:.3f} N**, "
        f"k = **{cal.k_N_per_mm:.3f} N/mm** (paper: 0.95 mm, 0.45 N, 0.48 N/mm)",
        f"* with them, five cycles: net advance {metrics.net_advance:.2f} mm (per cycle "
        + ", ".join(f"{a:.2f}" for a in metrics.advance_per_cycle)
        + f" mm), work {metrics.work:.2f} mJ",
        "",
        "Calibrated from our FE run (its advance and connector work over its cycles):",
        "",
        _fe_line(ours),
    ]
    values = metrics.to_dict() | {
        "paper_calibration": cal.as_dict(),
        "fe_calibration": ours,
    }
    return PartResult("reduced", values=values, figures=figs, lines=tuple(lines))


def _from_fe(ctx: Context) -> dict | None:
    """F_p/k, F_p and k that the FE run's own advance and work give, or None without it."""
    from bristlecrawler.errors import InputError
    from bristlecrawler.reduced import calibrate
    from bristlecrawler.results.keys import NET_ADVANCE_MM, WORK_MJ

    advance, work = ctx.value("fe-paper", NET_ADVANCE_MM), ctx.value("fe-paper", WORK_MJ)
    cycles = ctx.value("fe-paper", "cycles")
    if advance is None or work is None:
        return None
    try:
        cal = calibrate(S_MAX_MM, cycles, advance, work)
    except InputError as exc:  # an FE gait outside the closed forms' reach
        return {"error": str(exc)}
    return cal.as_dict() | {"cycles": cycles, "advance_mm": advance, keys.WORK_MJ: work}


def _fe_line(ours: dict | None) -> str:
    if ours is None:
        return "* not available: the FE part did not finish"
    if "error" in ours:
        return f"* not possible: {ours['error']}"
    return (
        f"* {ours['cycles']} cycle(s), {ours['advance_mm']:.2f} mm, {ours[keys.WORK_MJ]:.2f} mJ: "
        f"F_p/k = **{ours['fp_over_k_mm']:.3f} mm**, F_p = **{ours[keys.FP_N]:.3f} N**, "
        f"k = **{ours[keys.K_N_PER_MM]:.3f} N/mm**"
    )


REDUCED = Part(
    "reduced",
    "Reduced model and its calibration (Section 4, Figs. 8, 9, 10)",
    run_reduced,
    cost=0.5,
)
