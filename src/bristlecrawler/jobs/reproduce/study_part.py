"""Beyond the paper: a short design study of the bristles' inclination, through the sweep
machinery (:func:`bristlecrawler.studies.runner.run_sweep`, on a local Dask cluster).

The inclination reaches the two models differently. The FE crawler takes alpha itself:
one cycle of the paper's gait per inclination. The reduced model knows alpha only through
the grip of a bristle, F_p/k (a steeper bristle is stiffer and grips harder): it is swept
over F_p with k fixed, five cycles each, which shows where its closed forms' regimes (no
sliding, shakedown, steady crawling) begin.
"""

from __future__ import annotations

import numpy as np

from bristlecrawler.jobs.reproduce.parts import Context, Figure, Part, PartResult
from bristlecrawler.results import keys
from bristlecrawler.results.keys import NET_ADVANCE_MM

REDUCED_STUDY = """\
name = "grip"
description = "reduced two-bristle crawler, paper stroke, F_p from 0.05 to 6 N (k = 0.48 N/mm)"
model = "reduced"
base = "paper"

[set]
k = 0.48
cycles = 5

[axes]
fp = {{ linspace = [0.05, 6.0, {n}] }}
"""

FE_STUDY = """\
name = "inclination"
description = "FE crawler, bristle inclination {lo} to {hi} degrees, one cycle of the paper's gait"
model = "fe"
base = "paper"

[set]
"actuation.cycles" = 1
"bristle.elements" = {elements}
"output.vtk" = false
"output.figures" = false
"output.animation" = false

[axes]
"bristle.alpha_deg" = {{ linspace = [{lo}, {hi}, {n}] }}
"""


def _sweep(ctx: Context, name: str, text: str):
    """Run the study ``text`` in ``<folder>/study-<name>/``; its gathered Dataset."""
    import xarray as xr

    from bristlecrawler.io.atomic import atomic_write_text
    from bristlecrawler.studies.runner import SweepOptions, run_sweep

    path = atomic_write_text(ctx.folder / f"study-{name}.toml", text)
    options = SweepOptions(
        out=ctx.folder / f"study-{name}",
        workers=ctx.settings.workers,
        figures=False,
        progress=False,
        command="bristlecrawler reproduce",
    )
    summary = run_sweep(str(path), options)
    with xr.open_zarr(summary["store"]) as ds:
        return ds.load(), summary


def run_study(ctx: Context) -> PartResult:
    import importlib.util

    from bristlecrawler.viz.reduced import save_figure
    from bristlecrawler.viz.reproduce import plot_study

    missing = [m for m in ("distributed", "zarr") if importlib.util.find_spec(m) is None]
    if missing:  # an install without the studies extra: say so, it is not a failure
        text = (
            f"Not run: the design study needs {' and '.join(missing)} "
            '(`pip install -e ".[studies]"`).'
        )
        return PartResult("study", values={"skipped": text}, lines=(text,))
    n = 7 if ctx.settings.quick else 25
    red, red_sum = _sweep(ctx, "grip", REDUCED_STUDY.format(n=n))
    ctx.progress(0.2)
    c = red["fp"].values / 0.48
    figs = [
        Figure(
            "study-grip.png",
            "Reduced model: net advance and work over five cycles "
            "against the grip F_p/k (k = 0.48 N/mm).",
        )
    ]
    outputs = {
        "net advance, 5 cycles (mm)": red[NET_ADVANCE_MM].values,
        "work, 5 cycles (mJ)": red[keys.WORK_MJ].values,
    }
    save_figure(
        plot_study(c, outputs, "F_p/k (mm)", "reduced model: grip", _failed(red)),
        ctx.folder / figs[0].path,
    )
    adv = red[NET_ADVANCE_MM].values
    stopped = c[adv <= 1e-9]
    stop = f"{stopped[0]:.2f}" if stopped.size else f"more than {c[-1]:.1f}"
    lines = [
        f"Reduced model, {red_sum['designs_total']} designs of F_p/k from {c[0]:.2f} to "
        f"{c[-1]:.1f} mm (`study-grip.toml`, store `study-grip/study.zarr`): the advance "
        f"over five cycles falls from {np.nanmax(adv):.1f} mm as the grip grows and is "
        f"zero from F_p/k = {stop} mm on (the closed forms: no motion after the first "
        "cycle once F_p/k >= s~/4 = 5 mm, none at all once F_p/k >= s~/2 = 10 mm).",
    ]
    values = {"grip_designs": red_sum["designs_total"], "grip_done": red_sum["designs_done"]}
    if ctx.settings.study_fe:
        fe_figs, fe_lines, fe_values = _fe_inclination(ctx)
        figs += fe_figs
        lines += ["", *fe_lines]
        values |= fe_values
    else:
        lines += ["", "The FE inclination sweep is left out of `--quick`."]
    return PartResult("study", values=values, figures=tuple(figs), lines=tuple(lines))


def _failed(ds) -> np.ndarray:
    """Whether each design of a one-axis study failed or was lost."""
    from bristlecrawler.studies.evaluate import DesignStatus

    status = ds["status"].values
    return (status == DesignStatus.FAILED) | (status == DesignStatus.LOST)


def _fe_inclination(ctx: Context):
    from bristlecrawler.viz.reduced import save_figure
    from bristlecrawler.viz.reproduce import plot_study

    text = FE_STUDY.format(lo=15.0, hi=60.0, n=4, elements=ctx.settings.elements)
    ds, summary = _sweep(ctx, "inclination", text)
    alpha = ds["bristle.alpha_deg"].values
    fig = Figure(
        "study-inclination.png",
        "FE crawler: advance and work of one cycle against the bristles' inclination alpha.",
    )
    outputs = {
        "advance, 1 cycle (mm)": ds[NET_ADVANCE_MM].values,
        "work, 1 cycle (mJ)": ds[keys.WORK_MJ].values,
    }
    from bristlecrawler.scenario.load import load_scenario

    # The FE crawler advances by whole pitches: drawn, a pitch more or less is not an optimum.
    pitch = {"advance, 1 cycle (mm)": load_scenario("paper").substrate.pitch}
    title = "FE crawler: inclination"
    save_figure(
        plot_study(alpha, outputs, "inclination alpha (degrees)", title, _failed(ds), pitch),
        ctx.folder / fig.path,
    )
    rows = ", ".join(
        f"{a:g}°: {v:.2f} mm" for a, v in zip(alpha, ds[NET_ADVANCE_MM].values, strict=True)
    )
    lines = [
        f"FE crawler, {summary['designs_total']} inclinations, one cycle each "
        f"({summary['designs_done']} done, {summary['designs_failed']} failed; "
        f"`study-inclination.toml`): {rows}."
    ]
    failed = [str(e) for e in ds["error"].values if str(e)]
    lines += [f"* failed design: {e}" for e in failed]
    values = {
        "inclination_deg": alpha.tolist(),
        "inclination_advance_mm": [
            None if np.isnan(v) else float(v) for v in ds[NET_ADVANCE_MM].values
        ],
    }
    return [fig], lines, values


STUDY = Part(
    "study",
    "Beyond the paper: a design study of the inclination",
    run_study,
    cost=47.0,
    quick_cost=3.0,
)
