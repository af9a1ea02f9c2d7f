"""``bristlecrawler simulate``: the finite-element crawler (paper Section 3)."""

from __future__ import annotations

import shlex
import sys
from pathlib import Path
from typing import Annotated

import typer

from bristlecrawler.cli.options import JsonSummary, OutFolder, ReplaceRun, ShowProgress
from bristlecrawler.errors import printable


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
    out: OutFolder = None,
    replace: ReplaceRun = False,
    as_json: JsonSummary = False,
    no_figures: Annotated[
        bool, typer.Option("--no-figures", help="skip figures and animation")
    ] = False,
    no_vtk: Annotated[bool, typer.Option("--no-vtk", help="skip the ParaView series")] = False,
    progress: ShowProgress = None,
) -> None:
    """Run a finite-element crawler scenario: gravity step, then the prescribed stroke.

    Writes crawler.nc (xarray/NetCDF), vtk/crawler.pvd (ParaView), delta_vs_s.png,
    shapes.png, connector.png, crawler.gif (+ crawler.mp4 with the video extra),
    summary.json, config.json, scenario.toml (rerun it with simulate FILE), meta.json.
    """
    from bristlecrawler.fe import enable_compilation_cache
    from bristlecrawler.io.runs import check_out_dir
    from bristlecrawler.jobs.simulate import run_simulation, summary_json
    from bristlecrawler.scenario.cost import fe_crawler

    sc = _scenario(scenario, cycles, assign, actuator, history, no_figures, no_vtk)
    estimate = fe_crawler(sc)
    if estimate is not None:
        estimate.check()
    check_out_dir(out, replace)
    enable_compilation_cache()
    run = run_simulation(
        sc,
        out=out,
        progress=False if as_json else progress,
        command="bristlecrawler " + shlex.join(sys.argv[1:]),
        replace=replace,
        estimate=None if estimate is None else estimate.text(),
    )
    for w in (*run.notes, *run.summary["warnings"]):
        typer.echo(f"warning: {printable(w)}", err=True)
    _note_defaults(scenario)
    if run.out_dir is not None and sc.output.animation:
        _note_mp4()
    if as_json:
        typer.echo(summary_json(run.summary))
        return
    _print_summary(run.summary)


def _scenario(scenario, cycles, assign, actuator, history, no_figures, no_vtk):
    """The scenario with the command's options applied; InputError for options that
    contradict each other."""
    from bristlecrawler.errors import InputError
    from bristlecrawler.scenario.load import apply_overrides, apply_values, load_scenario

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
    if actuator is not None and sc.actuation.history is not None:
        sc = apply_values(sc, {"actuation.kind": actuator, "actuation.history": None})
    if sets:
        sc = apply_overrides(sc, sets)
    if history is not None:
        # Set as a value, not a TOML string (any file name), absolute (config.json reruns).
        path = str(history.expanduser().absolute())
        sc = apply_values(sc, {"actuation.kind": "history", "actuation.history": path})
    return sc


def _note_mp4() -> None:
    from bristlecrawler.viz.animation import mp4_available

    if not mp4_available():
        typer.echo(
            "note: crawler.gif written, no crawler.mp4: MP4 needs the video extra "
            "(pip install 'bristlecrawler[video]')",
            err=True,
        )


def _note_defaults(scenario: str) -> None:
    """Say which keys a scenario file leaves to a default that `paper` changes."""
    from bristlecrawler.scenario.keys import defaults_unlike_paper, toml_value
    from bristlecrawler.scenario.load import available_scenarios, scenario_document

    if scenario in available_scenarios() and not Path(scenario).is_file():
        return
    keys = defaults_unlike_paper(scenario_document(scenario))
    if keys:
        listed = ", ".join(
            f"{k.key} = {toml_value(k.default)} (paper: {toml_value(k.paper)})" for k in keys
        )
        typer.echo(
            f"note: {printable(scenario)} leaves {listed} at the schema's default; "
            'add base = "paper" to start from the paper scenario',
            err=True,
        )


def _print_summary(summary: dict) -> None:
    from rich.console import Console
    from rich.table import Table

    from bristlecrawler.results.metrics import RunMetrics

    m = RunMetrics.from_dict(summary)
    table = Table(title=f"finite-element crawler: {summary['scenario']}")
    table.add_column("quantity")
    table.add_column("value", justify="right")
    table.add_row("net advance (mm)", f"{m.net_advance:.3f}")
    table.add_row("advance per cycle (mm)", ", ".join(f"{a:.2f}" for a in m.advance_per_cycle))
    table.add_row("connector work W_c (mJ)", f"{m.work:.3f}")
    table.add_row("mean |F_c| (N)", f"{summary['mean_abs_connector_force_N']:.3f}")
    table.add_row("energy balance residual / W_c", f"{summary['energy_balance_rel_error']:.1e}")
    table.add_row("first frequency (Hz)", f"{summary['first_frequency_hz']:.2f}")
    table.add_row("largest bending strain of a bristle", f"{summary['max_bristle_strain']:.3f}")
    table.add_row(
        "steps / Newton iterations / rejected",
        f"{summary['steps']} / {summary['newton_iterations']} / {summary['rejected_steps']}",
    )
    table.add_row("wall time (s)", f"{summary['wall_time_s']:.1f}")
    console = Console()
    console.print(table)
    console.print(
        "W_c: work of the actuator on the connector. The balance residual is W_c minus the "
        "energy stored and dissipated (elastic, kinetic, gravity, friction, damping): "
        "mostly what the implicit integrator loses when a tip snaps into a groove or off a "
        "land edge faster than the steps resolve (see the docs' findings page)."
    )
    if "output_dir" in summary:
        console.print(f"results in {printable(summary['output_dir'])}", markup=False)


def register(app: typer.Typer) -> None:
    app.command("simulate")(simulate_cmd)
