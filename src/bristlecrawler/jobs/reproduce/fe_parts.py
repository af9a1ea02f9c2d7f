"""The finite-element crawler (paper Section 3): alpha = pi/4 (Figs. 5, 6, 7) and the
alpha = 0 control.

At alpha = 0 each cycle moves the crawler by whole groove pitches one way or the other,
decided by round-off (docs/findings.md), so one five-cycle run says little: the part runs
one cycle from several starting places of the tips on the texture (the substrate shifted
by fractions of a pitch) and reports the mean advance per cycle with its standard error.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from bristlecrawler.jobs.reproduce.parts import Context, Figure, Part, PartResult
from bristlecrawler.results import keys


def scenario(name: str, ctx: Context, sets: list[str]):
    """Shipped scenario ``name`` at the settings' mesh, with the assignments ``sets``."""
    from bristlecrawler.scenario.load import apply_overrides, load_scenario

    return apply_overrides(
        load_scenario(name), [f"bristle.elements={ctx.settings.elements}", *sets]
    )


def solve(sc, ctx: Context, share: tuple[float, float] = (0.0, 1.0)):
    """Run scenario ``sc``; progress goes to the part's bar as the ``share`` (from, to) of
    the part this run covers."""
    from bristlecrawler.crawler import build, run
    from bristlecrawler.jobs.estimates import compile_announcer
    from bristlecrawler.scenario.convert import to_spec

    lo, hi = share
    spec = to_spec(sc)
    compiling = compile_announcer(spec, ctx.note)

    def show(p):
        compiling.seen(p.stage)
        if p.t_end > 0:
            ctx.progress(lo + (hi - lo) * min(max(p.t / p.t_end, 0.0), 1.0))

    h = run(build(spec), on_progress=show)
    compiling.done(h.stats)
    return h


def run_paper(ctx: Context) -> PartResult:
    from bristlecrawler.jobs.simulate import frame_subset, summarize
    from bristlecrawler.results.metrics import RunMetrics
    from bristlecrawler.viz.crawler import animate, plot_connector, plot_delta_vs_s, plot_shapes
    from bristlecrawler.viz.reduced import save_figure

    n = ctx.settings.fe_cycles
    sc = scenario("paper", ctx, [f"actuation.cycles={n}"])
    h = solve(sc, ctx, (0.0, 0.8))
    summary = summarize(h, sc)
    figs = (
        Figure(
            "fe-delta-vs-s.png",
            f"Delta(s) over {n} cycles, stick dashed, slip solid: paper Fig. 5.",
        ),
        Figure(
            "fe-shapes.png",
            "Deformed shapes at the start, full contraction and "
            "re-extension of each cycle: paper Fig. 6.",
        ),
        Figure(
            "fe-connector.png",
            "Connector force F_c(t) and work W_c(t), the first cycle shaded: paper Fig. 7.",
        ),
        Figure("fe-crawler.gif", "The crawler over the whole run (animation)."),
    )
    title = f"paper: alpha = 45 deg, net {h.net_advance:.2f} mm over {_cycles(n)}"
    save_figure(plot_delta_vs_s(h, title=title), ctx.folder / figs[0].path)
    save_figure(plot_shapes(h), ctx.folder / figs[1].path)
    save_figure(plot_connector(h), ctx.folder / figs[2].path)
    ctx.progress(0.85)
    keep = frame_subset(h, ctx.settings.frames_per_cycle)
    framed = dataclasses.replace(h, frame_t=h.frame_t[keep], frame_nodes=h.frame_nodes[keep])
    animate(framed, ctx.folder / "fe-crawler")
    metrics = RunMetrics.from_dict(summary)
    per_cycle = ", ".join(f"{a:.3f}" for a in metrics.advance_per_cycle)
    lines = [
        f"The shipped `paper` scenario (alpha = 45 degrees, {sc.bristle.elements} elements "
        f"per bristle, {_cycles(n)} of s = 20 sin²(πt/20) mm; `bristlecrawler simulate paper` "
        "writes the same run with its NetCDF and ParaView files).",
        "",
        f"* net advance **{metrics.net_advance:.3f} mm** (per cycle: {per_cycle} mm)",
        f"* connector work W_c = **{metrics.work:.2f} mJ**, mean |F_c| = "
        f"{summary['mean_abs_connector_force_N']:.3f} N",
        f"* energy balance residual {summary['energy_balance_rel_error']:.1%} of W_c; "
        f"{summary['steps']} steps, {summary['newton_iterations']} Newton iterations",
    ]
    lines += [f"* warning: {w}" for w in summary["warnings"]]
    extra = (
        keys.MEAN_ABS_CONNECTOR_FORCE_N,
        keys.ENERGY_BALANCE_REL_ERROR,
        keys.STEPS,
        keys.WALL_TIME_S,
    )
    values = metrics.to_dict() | {k: summary[k] for k in extra}
    values |= {"cycles": n, "elements": sc.bristle.elements}
    return PartResult("fe-paper", values=values, figures=figs, lines=tuple(lines))


def run_vertical(ctx: Context) -> PartResult:
    from bristlecrawler.errors import SolverError
    from bristlecrawler.viz.reduced import save_figure
    from bristlecrawler.viz.reproduce import plot_vertical

    m = ctx.settings.vertical_phases
    pitch = scenario("paper-vertical", ctx, []).substrate.pitch
    phases = pitch * np.arange(m) / m
    runs, failed = [], []
    for j, phase in enumerate(phases):
        sc = scenario(
            "paper-vertical", ctx, ["actuation.cycles=1", f"substrate.phase={float(phase)!r}"]
        )
        try:
            runs.append((float(phase), solve(sc, ctx, (j / m, (j + 1) / m))))
        except SolverError as exc:
            failed.append(f"start {phase:g} mm: {' '.join(str(exc).split())}")
    if not runs:
        raise SolverError("every starting place failed: " + "; ".join(failed))
    adv = np.array([h.net_advance for _, h in runs])
    mean = float(adv.mean())
    sem = float(adv.std(ddof=1) / np.sqrt(adv.size)) if adv.size > 1 else float("nan")
    inclined = ctx.value("fe-paper", keys.ADVANCE_PER_CYCLE_MM)
    fig = Figure(
        "fe-vertical.png",
        "alpha = 0: Delta(s) of one cycle from each starting "
        "place (left), and the advance of each against the starting place, with "
        "alpha = pi/4's cycles for scale (right).",
    )
    save_figure(
        plot_vertical([p for p, _ in runs], [h for _, h in runs], inclined), ctx.folder / fig.path
    )
    listed = ", ".join(f"{p:g} mm: {a:+.2f}" for (p, _), a in zip(runs, adv, strict=True))
    where = (
        f"one cycle from each of {m} starting places of the tips on the texture (the "
        f"grooves shifted by 0 to {phases[-1]:g} mm of the {pitch:g} mm pitch)"
        if m > 1
        else "one cycle from one starting place of the tips on the texture"
    )
    lines = [
        f"The shipped `paper-vertical` scenario (alpha = 0), {where}, "
        f"{ctx.settings.elements} elements per bristle.",
        "",
        f"* advance of each cycle (shift: advance, mm): {listed}",
        f"* mean advance per cycle **{mean:+.2f} mm**, standard error "
        f"{_fmt(sem)} mm (paper: no appreciable net advancement)",
        "* Each cycle moves by whole pitches either way: which tip slips first at a groove "
        "event is decided by round-off, so the mean over starting places, not one run, is "
        "the measure.",
    ]
    lines += [f"* failed: {f}" for f in failed]
    values = {
        "advance_per_cycle_mean_mm": mean,
        "advance_per_cycle_sem_mm": None if np.isnan(sem) else sem,
        keys.ADVANCE_PER_CYCLE_MM: adv.tolist(),
        "starting_places_mm": [p for p, _ in runs],
        "failed_starting_places": len(failed),
    }
    return PartResult("fe-vertical", values=values, figures=(fig,), lines=tuple(lines))


def _cycles(n: int) -> str:
    return "1 cycle" if n == 1 else f"{n} cycles"


def _fmt(x: float) -> str:
    return "n/a (one place)" if np.isnan(x) else f"{x:.2f}"


FE_PAPER = Part(
    "fe-paper",
    "Finite-element model, alpha = pi/4 (Section 3, Figs. 5, 6, 7)",
    run_paper,
    cost=117.0,
    quick_cost=77.0,
)
FE_VERTICAL = Part(
    "fe-vertical",
    "Finite-element model, alpha = 0: the control (Section 3)",
    run_vertical,
    cost=355.0,
    quick_cost=37.0,
)
