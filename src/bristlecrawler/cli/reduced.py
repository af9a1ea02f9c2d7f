"""``bristlecrawler reduced`` and ``bristlecrawler calibrate``: the reduced 1-D model."""

from __future__ import annotations

import shlex
import sys
from pathlib import Path
from typing import Annotated

import typer

from bristlecrawler.cli.options import JsonSummary, OutFolder, ReplaceRun
from bristlecrawler.errors import printable
from bristlecrawler.reduced.crawler import (
    DEFAULT_FN_OVER_FP,
    PAPER_CYCLES,
    PAPER_FP,
    PAPER_K,
    PAPER_LENGTH,
    PAPER_PERIOD,
    PAPER_S_MAX,
)
from bristlecrawler.results import keys


def reduced_cmd(
    s_max: Annotated[
        float, typer.Option("--s-max", help="peak shortening s~ per segment, mm")
    ] = PAPER_S_MAX,
    fp: Annotated[
        float,
        typer.Option(
            "--fp",
            help=f"F_p, resistance along the grain, N [default: {PAPER_FP:.6g}]",
            show_default=False,
        ),
    ] = PAPER_FP,
    fn: Annotated[
        float | None,
        typer.Option(
            "--fn",
            help=f"F_n, resistance against the grain, N [default: {DEFAULT_FN_OVER_FP:g} x fp]",
        ),
    ] = None,
    k: Annotated[float, typer.Option("--k", help="bristle stiffness, N/mm")] = PAPER_K,
    length: Annotated[
        float, typer.Option("--length", help="distance between the end bristles, mm")
    ] = PAPER_LENGTH,
    cycles: Annotated[int, typer.Option("--cycles", help="number of strokes")] = PAPER_CYCLES,
    period: Annotated[float, typer.Option("--period", help="stroke period T, s")] = PAPER_PERIOD,
    bristles: Annotated[int, typer.Option("--bristles", help="number of bristles N (>= 2)")] = 2,
    gait: Annotated[str, typer.Option("--gait", help="breathing | peristaltic")] = "breathing",
    lag: Annotated[
        float | None,
        typer.Option(
            "--lag", help="peristaltic delay between neighbouring segments, s [default: period/4]"
        ),
    ] = None,
    stroke: Annotated[
        str,
        typer.Option("--stroke", help="sin2 | triangle (rate-independent model: same Delta(s))"),
    ] = "sin2",
    actuator: Annotated[
        str, typer.Option("--actuator", help="sin2 (prescribed) | sma (closed-loop SMA model)")
    ] = "sin2",
    history: Annotated[
        Path | None,
        typer.Option(
            "--history",
            help="CSV with header and columns t (s), s (mm), instead of the sin^2 stroke",
        ),
    ] = None,
    texture: Annotated[
        Path | None,
        typer.Option(
            "--texture",
            help="a drag test's summary.json: the crawler on its texture law (then --fp, --fn "
            "and --k are not used)",
        ),
    ] = None,
    samples: Annotated[int, typer.Option("--samples-per-cycle", help="samples per period")] = 2000,
    out: OutFolder = None,
    replace: ReplaceRun = False,
    as_json: JsonSummary = False,
    no_figures: Annotated[bool, typer.Option("--no-figures", help="skip the PNG figures")] = False,
) -> None:
    """Run the reduced one-dimensional model (paper Section 4) with the exact solver.

    Defaults are the paper's: s~ = 20 mm, F_p/k = 0.95 mm, k = 0.48 N/mm, L = 100 mm,
    5 cycles of s(t) = s~ sin^2(pi t / T), T = 20 s. Writes reduced.nc (xarray/NetCDF),
    delta_vs_s.png, friction_law.png, summary.json, config.json and meta.json.
    """
    from bristlecrawler.jobs.reduced import run_reduced
    from bristlecrawler.scenario.reduced import ReducedConfig
    from bristlecrawler.scenario.strict import option_names, parse_model

    config = parse_model(
        ReducedConfig,
        {
            "s_max": s_max,
            "fp": fp,
            "fn": fn,
            "k": k,
            "length": length,
            "cycles": cycles,
            "period": period,
            "bristles": bristles,
            "gait": gait,
            "lag": lag,
            "stroke": stroke,
            "actuator": actuator,
            "history": None if history is None else str(history),
            "texture": None if texture is None else str(texture),
            "samples_per_cycle": samples,
        },
        option_names(ReducedConfig, samples_per_cycle="--samples-per-cycle"),
    )
    run = run_reduced(
        config,
        out=out,
        figures=not no_figures,
        command="bristlecrawler " + shlex.join(sys.argv[1:]),
        replace=replace,
    )
    _report(run, as_json)


def _report(run, as_json: bool) -> None:
    """The run's warnings on stderr, then its summary as JSON or as a table."""
    from bristlecrawler.io.jsonio import dumps_strict

    for line in (*run.notes, *run.summary.get("warnings", ())):
        typer.echo(f"warning: {printable(line)}", err=True)
    if as_json:
        typer.echo(dumps_strict(run.summary))
        return
    _print_summary(run.summary)


def _print_summary(summary: dict) -> None:
    from rich.console import Console
    from rich.table import Table

    from bristlecrawler.results.metrics import RunMetrics

    m = RunMetrics.from_dict(summary)
    table = Table(title="reduced model", show_header=True)
    table.add_column("quantity")
    table.add_column("value", justify="right")
    table.add_row("net advance (mm)", f"{m.net_advance:.4f}")
    if "closed_form_net_advance_mm" in summary:
        table.add_row("  closed form (mm)", f"{summary['closed_form_net_advance_mm']:.4f}")
    table.add_row("advance per cycle (mm)", ", ".join(f"{a:.3f}" for a in m.advance_per_cycle))
    table.add_row("actuator work (mJ)", f"{m.work:.4f}")
    if "closed_form_work_mJ" in summary:
        table.add_row("  closed form (mJ)", f"{summary['closed_form_work_mJ']:.4f}")
    table.add_row(
        "work per cycle (mJ)", ", ".join(f"{w:.3f}" for w in summary[keys.WORK_PER_CYCLE_MJ])
    )
    if "regime" in summary:
        table.add_row("regime", str(summary["regime"]))
    table.add_row("energy balance, rel. error", f"{summary['energy_balance_rel_error']:.1e}")
    table.add_row("stick/slip events", str(summary["events"]))
    console = Console()
    console.print(table)
    if summary.get("gait") == "peristaltic" and summary.get("bristles", 2) > 2:
        console.print(
            "per cycle: each period T of the first segment; the wave takes (N - 2) lags "
            "more to pass along the body, so the first cycles (the wave entering) and the "
            "last (it leaving) differ from the steady ones, and can be negative"
        )
    if "output_dir" in summary:
        console.print(f"results in {printable(summary['output_dir'])}", markup=False)


def calibrate_cmd(
    s_max: Annotated[float, typer.Option("--s-max", help="peak shortening s~, mm")],
    cycles: Annotated[int, typer.Option("--cycles", help="number of cycles n")],
    advance: Annotated[float, typer.Option("--advance", help="net advance after n cycles, mm")],
    work: Annotated[
        float | None, typer.Option("--work", help="actuator work over n cycles, mJ")
    ] = None,
    as_json: Annotated[bool, typer.Option("--json", help="print JSON on stdout")] = False,
) -> None:
    """Calibrate F_p/k (and, with --work, F_p and k) from a measured gait (paper Section 4)."""
    from bristlecrawler.io.jsonio import dumps_strict
    from bristlecrawler.reduced.calibration import calibrate

    cal = calibrate(s_max, cycles, advance, work)
    d = cal.as_dict()
    if as_json:
        typer.echo(dumps_strict(d))
        return
    typer.echo(f"F_p/k = {cal.fp_over_k_mm:.4f} mm (regime {cal.regime})")
    if cal.fp_N is not None:
        typer.echo(f"F_p   = {cal.fp_N:.4f} N")
        typer.echo(f"k     = {cal.k_N_per_mm:.4f} N/mm")


def register(app: typer.Typer) -> None:
    app.command("reduced")(reduced_cmd)
    app.command("calibrate")(calibrate_cmd)
