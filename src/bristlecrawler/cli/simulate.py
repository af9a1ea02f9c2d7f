"""``bristlecrawler simulate``: the finite-element crawler (paper Section 3)."""

from __future__ import annotations

import shlex
import sys
from pathlib import Path
from typing import Annotated

import typer


def simulate_cmd(
    scenario: Annotated[
        str, typer.Argument(help="shipped scenario (paper, paper-vertical) or a TOML file")
    ] = "paper",
    cycles: Annotated[
        int | None, typer.Option("--cycles", help="number of cycles [default: the scenario's]")
    ] = None,
    assign: Annotated[
        list[str] | None,
        typer.Option(
            "--set",
            help="override a scenario value, section.key=value (TOML value), repeatable; "
            "e.g. --set bristle.alpha_deg=0 --set substrate.pitch=3.0",
        ),
    ] = None,
    actuator: Annotated[
        str | None,
        typer.Option(
            "--actuator",
            help="sin2 (prescribed s~ sin^2(pi t/T)) | sma (closed-loop SMA actuator model) "
            "[default: the scenario's actuation.kind]; for a recorded history use --history",
        ),
    ] = None,
    history: Annotated[
        Path | None,
        typer.Option(
            "--history",
            help="CSV of a shortening history, columns t (s) and s (mm), s >= 0 and below "
            "the body length (sets actuation.kind = history)",
        ),
    ] = None,
    out: Annotated[
        Path | None, typer.Option("--out", help="output folder [default: runs/<id>]")
    ] = None,
    replace: Annotated[
        bool,
        typer.Option(
            "--replace", help="replace the run (complete or not) in --out once this one is done"
        ),
    ] = False,
    as_json: Annotated[bool, typer.Option("--json", help="print a JSON summary on stdout")] = False,
    no_figures: Annotated[
        bool, typer.Option("--no-figures", help="skip figures and animation")
    ] = False,
    no_vtk: Annotated[bool, typer.Option("--no-vtk", help="skip the ParaView series")] = False,
    progress: Annotated[
        bool | None,
        typer.Option("--progress/--no-progress", help="progress bar [default: on a terminal]"),
    ] = None,
) -> None:
    """Run a finite-element crawler scenario: gravity step, then the prescribed stroke.

    Writes crawler.nc (xarray/NetCDF), vtk/crawler.pvd (ParaView), delta_vs_s.png,
    shapes.png, connector.png, crawler.gif (+ .mp4), summary.json, config.json, meta.json.
    """
    from bristlecrawler.errors import InputError
    from bristlecrawler.fe import enable_compilation_cache
    from bristlecrawler.jobs.simulate import (
        apply_overrides,
        apply_values,
        run_simulation,
        summary_json,
    )
    from bristlecrawler.scenario.load import load_scenario

    sc = load_scenario(scenario)
    sets = list(assign or [])
    if cycles is not None:
        sets.append(f"actuation.cycles={cycles}")
    if actuator is not None:
        if actuator not in ("sin2", "sma"):
            raise InputError(f"--actuator must be sin2 or sma, got {actuator!r}")
        if history is not None:
            raise InputError("give --actuator or --history, not both")
        sets.append(f'actuation.kind="{actuator}"')
    if history is not None and cycles is not None:
        raise InputError("--cycles does not apply to --history (the file sets the stroke)")
    if no_figures:
        sets += ["output.figures=false", "output.animation=false"]
    if no_vtk:
        sets.append("output.vtk=false")
    if sets:
        sc = apply_overrides(sc, sets)
    if history is not None:
        # Set as a value, not a TOML string (any file name), absolute (config.json reruns).
        path = str(history.expanduser().absolute())
        sc = apply_values(sc, {"actuation.kind": "history", "actuation.history": path})
    enable_compilation_cache()
    run = run_simulation(
        sc,
        out=out,
        progress=False if as_json else progress,
        command="bristlecrawler " + shlex.join(sys.argv[1:]),
        replace=replace,
    )
    for w in (*run.notes, *run.summary["warnings"]):
        typer.echo(f"warning: {w}", err=True)
    if as_json:
        typer.echo(summary_json(run.summary))
        return
    _print_summary(run.summary)


def _print_summary(summary: dict) -> None:
    from rich.console import Console
    from rich.table import Table

    table = Table(title=f"finite-element crawler: {summary['scenario']}")
    table.add_column("quantity")
    table.add_column("value", justify="right")
    table.add_row("net advance (mm)", f"{summary['net_advance_mm']:.3f}")
    table.add_row(
        "advance per cycle (mm)", ", ".join(f"{a:.2f}" for a in summary["advance_per_cycle_mm"])
    )
    table.add_row("connector work (mJ)", f"{summary['work_mJ']:.3f}")
    table.add_row("mean |F_c| (N)", f"{summary['mean_abs_connector_force_N']:.3f}")
    table.add_row("energy balance, rel. error", f"{summary['energy_balance_rel_error']:.1e}")
    table.add_row("first frequency (Hz)", f"{summary['first_frequency_hz']:.2f}")
    table.add_row("largest bending strain of a bristle", f"{summary['max_bristle_strain']:.3f}")
    table.add_row(
        "steps / Newton iterations / rejected",
        f"{summary['steps']} / {summary['newton_iterations']} / {summary['rejected_steps']}",
    )
    table.add_row("wall time (s)", f"{summary['wall_time_s']:.1f}")
    console = Console()
    console.print(table)
    if "output_dir" in summary:
        console.print(f"results in {summary['output_dir']}")


def register(app: typer.Typer) -> None:
    app.command("simulate")(simulate_cmd)
