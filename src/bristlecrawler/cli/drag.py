"""``bristlecrawler drag``: a virtual drag test of one bristle of a scenario."""

from __future__ import annotations

import shlex
import sys
from typing import Annotated

import typer

from bristlecrawler.cli.options import JsonSummary, OutFolder, ReplaceRun, ShowProgress
from bristlecrawler.errors import printable
from bristlecrawler.results import keys


def drag_cmd(
    scenario: Annotated[
        str, typer.Argument(help="shipped scenario (paper, paper-vertical) or a TOML file")
    ] = "paper",
    direction: Annotated[
        str,
        typer.Option(
            "--direction",
            help="along (+x, the grain) | against (-x) | cycle (both, back and forth)",
        ),
    ] = "cycle",
    distance: Annotated[
        float, typer.Option("--distance", help="travel of each leg, mm (>= one pitch)")
    ] = 20.0,
    speed: Annotated[float, typer.Option("--speed", help="carriage speed, mm/s")] = 2.0,
    legs: Annotated[int, typer.Option("--legs", help="legs of a cycle (>= 2)")] = 2,
    load: Annotated[
        float | None,
        typer.Option("--load", help="vertical load, N [default: the bristle's weight share]"),
    ] = None,
    assign: Annotated[
        list[str] | None,
        typer.Option("--set", help="override a scenario value, section.key=value; repeatable"),
    ] = None,
    out: OutFolder = None,
    replace: ReplaceRun = False,
    as_json: JsonSummary = False,
    progress: ShowProgress = None,
) -> None:
    """Drag one bristle of a scenario over its substrate: k, F_p, F_n of the reduced model.

    Writes drag.nc (xarray/NetCDF), drag.png, summary.json, config.json, meta.json.
    """
    from bristlecrawler.crawler.drag import quasi_static_ratio
    from bristlecrawler.fe import enable_compilation_cache
    from bristlecrawler.io.runs import check_out_dir
    from bristlecrawler.jobs.drag import run_drag
    from bristlecrawler.jobs.simulate import summary_json
    from bristlecrawler.scenario.convert import to_spec
    from bristlecrawler.scenario.drag import DragOptions, drag_estimate
    from bristlecrawler.scenario.load import apply_overrides, load_scenario
    from bristlecrawler.scenario.strict import option_names, parse_model

    values = {"direction": direction, "distance": distance, "speed": speed, "legs": legs}
    opts = parse_model(DragOptions, values | {"load": load}, option_names(DragOptions))
    sc = load_scenario(scenario)
    if assign:
        sc = apply_overrides(sc, list(assign))
    test = opts.test()
    spec = to_spec(sc)
    test.check(spec)  # bad input: one line, before the warning and any work
    estimate = drag_estimate(sc, test).check()
    check_out_dir(out, replace)
    notes = _notes(quasi_static_ratio(spec, test), speed)
    enable_compilation_cache()
    run = run_drag(
        sc,
        test,
        out=out,
        progress=False if as_json else progress,
        command="bristlecrawler " + shlex.join(sys.argv[1:]),
        replace=replace,
        # Said once the folder is claimed: a refusal after them would make bad input two lines.
        on_start=lambda: [typer.echo(printable(n), err=True) for n in notes],
        estimate=estimate.text(),
    )
    for warning in run.summary["warnings"]:
        typer.echo(f"warning: {printable(warning)}", err=True)
    if as_json:
        typer.echo(summary_json(run.summary))
        return
    _print(run.summary)


def _notes(ratio: float, speed: float) -> list[str]:
    """What to say once the test starts (said earlier, a refusal after them would make
    bad input more than one line)."""
    notes = []
    if ratio > 0.05:
        notes.append(
            f"warning: --speed {speed:g} mm/s is not quasi-static for this bristle (it crosses "
            f"a pitch in {1 / ratio:.3g} of its first periods; keep that above 20)"
        )
    return notes


def _print(s: dict) -> None:
    from rich.console import Console
    from rich.table import Table

    table = Table(title="drag test")
    table.add_column("quantity")
    table.add_column("value", justify="right")
    rows = [
        ("k, first loading to F_p (N/mm)", keys.K_N_PER_MM),
        ("k after a reversal (N/mm)", "k_unload_N_per_mm"),
        ("k, tangent while the tip sticks (N/mm)", "k_initial_N_per_mm"),
        ("F_p, sliding along (N)", keys.FP_N),
        ("  scatter over pitches (N)", "fp_scatter_N"),
        ("F_n, sliding against (N)", keys.FN_N),
        ("  scatter over pitches (N)", "fn_scatter_N"),
        ("F_p / k (mm)", "fp_over_k_mm"),
        ("mu times the load (N)", "mu_load_N"),
        ("dissipation (mJ/mm)", "dissipation_mJ_per_mm"),
    ]
    for label, key in rows:
        table.add_row(label, f"{s[key]:.4g}")
    console = Console()
    console.print(table)
    if "output_dir" in s:
        console.print(f"results in {printable(s['output_dir'])}", markup=False)


def register(app: typer.Typer) -> None:
    app.command("drag")(drag_cmd)
