"""The reduced model's parameters measured on the FE bristle: a virtual drag test, and the
reduced model fed with them against the FE crawler.

The paper identifies k and F_p from the crawler's advance and work (Section 4); a drag
test measures them on one bristle dragged back and forth over the texture under its share
of the weight (:func:`bristlecrawler.crawler.drag.drag_test`). The check here feeds the
measured k, F_p and F_n to the two-bristle reduced model over the FE run's cycles and
compares its advance with the FE crawler's.
"""

from __future__ import annotations

import math

from bristlecrawler.jobs.reproduce.parts import Context, Figure, Part, PartResult
from bristlecrawler.results import keys


def run_drag(ctx: Context) -> PartResult:
    from bristlecrawler.crawler.drag import DragTest, drag_test
    from bristlecrawler.jobs.estimates import compile_announcer
    from bristlecrawler.jobs.reproduce.fe_parts import scenario
    from bristlecrawler.scenario.convert import to_spec
    from bristlecrawler.viz.drag import plot_drag
    from bristlecrawler.viz.reduced import save_figure

    spec = to_spec(scenario("paper", ctx, []))
    test = DragTest(direction="cycle", distance=ctx.settings.drag_distance)

    compiling = compile_announcer(spec, ctx.note, "drag")

    def show(p):
        compiling.seen(p.stage)
        if p.t_end > 0:
            ctx.progress(min(max(p.t / p.t_end, 0.0), 1.0))

    r = drag_test(spec, test, on_progress=show)
    compiling.done(r.stats)
    s = r.summary()
    fig = Figure(
        "drag.png",
        "Drag test of one paper bristle: force against carriage "
        "travel, stick dashed, slip solid, the sliding means F_p and -F_n and the "
        "first-loading slope k marked.",
    )
    save_figure(plot_drag(r, title="paper bristle: drag test"), ctx.folder / fig.path)
    k, fp, fn = s[keys.K_N_PER_MM], s[keys.FP_N], s[keys.FN_N]
    lines = [
        f"One bristle of `paper` ({ctx.settings.elements} elements) dragged along and "
        f"against the grain over {test.distance:g} mm legs at {test.speed:g} mm/s under its "
        f"share of the weight ({s['load_N']:.3f} N; `bristlecrawler drag paper`):",
        "",
        f"* k = **{_n(k)} N/mm** (first-loading slope), F_p = **{_n(fp)} N** (whole-pitch "
        f"mean along the grain), F_n = **{_n(fn)} N** (against it); mu times the load "
        f"{s['mu_load_N']:.3f} N",
    ]
    values = {keys.K_N_PER_MM: _v(k), keys.FP_N: _v(fp), keys.FN_N: _v(fn), "load_N": s["load_N"]}
    check = _prediction(ctx, k, fp, fn)
    if check is not None:
        values["prediction"] = check
        lines.append(
            f"* prediction check: the reduced model with these k, F_p, F_n advances "
            f"**{check['reduced_mm']:.2f} mm** over {check['cycles']} cycle(s), the FE crawler "
            f"{check['fe_mm']:.2f} mm ({check['reduced_mm'] - check['fe_mm']:+.2f} mm)"
        )
    return PartResult("drag", values=values, figures=(fig,), lines=tuple(lines))


def _prediction(ctx: Context, k: float, fp: float, fn: float) -> dict | None:
    """The reduced model fed with the drag test's parameters over the FE run's cycles, or
    None when the FE run or a parameter is missing."""
    from bristlecrawler.reduced import ReducedCrawler, Sin2Stroke, simulate
    from bristlecrawler.results.keys import NET_ADVANCE_MM

    fe = ctx.value("fe-paper", NET_ADVANCE_MM)
    cycles = ctx.value("fe-paper", "cycles")
    if fe is None or not all(math.isfinite(v) and v > 0 for v in (k, fp, fn)):
        return None
    crawler = ReducedCrawler.from_drag({keys.K_N_PER_MM: k, keys.FP_N: fp, keys.FN_N: fn})
    res = simulate(crawler, Sin2Stroke(20.0, 20.0), cycles=cycles)
    return {"cycles": cycles, "reduced_mm": res.net_advance, "fe_mm": fe}


def _n(x: float) -> str:
    return f"{x:.3f}" if math.isfinite(x) else "n/a"


def _v(x: float) -> float | None:
    return float(x) if math.isfinite(x) else None


DRAG = Part(
    "drag",
    "Drag test: the reduced model's parameters measured on the FE bristle",
    run_drag,
    cost=125.0,
    quick_cost=61.0,
)
