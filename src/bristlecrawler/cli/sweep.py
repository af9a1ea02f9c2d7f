"""``bristlecrawler sweep``: a design study of the reduced or the FE model on Dask."""

from __future__ import annotations

import json
import shlex
import sys
from pathlib import Path
from typing import Annotated

import typer

from bristlecrawler.cli.options import JsonSummary
from bristlecrawler.errors import printable


def shipped_studies() -> dict[str, list[str]]:
    """The shipped studies' names by model (``reduced``, ``fe``), read from their files,
    so that the help lists what the package holds."""
    import tomllib
    from importlib import resources

    by_model: dict[str, list[str]] = {}
    folder = resources.files("bristlecrawler") / "studies"
    for entry in sorted(folder.iterdir(), key=lambda p: p.name):
        if entry.name.endswith(".toml"):
            model = tomllib.loads(entry.read_text(encoding="utf-8")).get("model", "?")
            by_model.setdefault(model, []).append(entry.name[:-5])
    return by_model


def _study_help() -> str:
    shipped = shipped_studies()
    reduced = ", ".join(shipped.get("reduced", []))
    fe = ", ".join(shipped.get("fe", []))
    return (
        f"a shipped study or a TOML file. Shipped: {reduced} (reduced model: seconds); "
        f"{fe} (FE model: minutes per design)"
    )


def sweep_cmd(
    study: Annotated[str, typer.Argument(help=_study_help())],
    out: Annotated[
        Path | None,
        typer.Option("--out", help="study folder [default: runs/<stamp>-sweep-<name>]"),
    ] = None,
    scheduler: Annotated[
        str | None,
        typer.Option(
            "--scheduler",
            help="address of a running Dask scheduler, e.g. tcp://host:8786 "
            "[default: a local cluster of processes]",
        ),
    ] = None,
    workers: Annotated[
        int | None,
        typer.Option("--workers", help="workers of the local cluster [default: one per core]"),
    ] = None,
    resume: Annotated[
        bool,
        typer.Option(
            "--resume", help="complete the study already in --out, skipping its done designs"
        ),
    ] = False,
    batch: Annotated[
        int | None,
        typer.Option(
            "--batch",
            help="FE designs of one structure per compiled batch (vmapped) "
            "[default: none on a CPU, up to 1024 on a GPU]",
        ),
    ] = None,
    as_json: JsonSummary = False,
    no_figures: Annotated[bool, typer.Option("--no-figures", help="skip the figures")] = False,
    progress: Annotated[
        bool | None,
        typer.Option(
            "--progress/--no-progress",
            help="progress bar [default: a bar on a terminal, else one line per finished design]",
        ),
    ] = None,
) -> int:
    """Run a design study: a grid of designs of the reduced model or the FE model.

    Every design of the study file's axes runs as one Dask task (chunks of designs for the
    reduced model), each result written the moment it ends. The reduced model's studies take
    seconds; the FE model's take minutes per design.

    Writes study.json, meta.json, parts/ (one file per finished task), study.zarr (every
    output on the design axes), designs.csv and figures/ in the study folder. Killed, the
    same command with --resume completes it. Exit code 1 if a design failed or was lost
    (the last lines list them with their reasons; the others' results are written), 2 on
    bad input (nothing written).
    """
    from bristlecrawler.studies.runner import SweepOptions, run_sweep

    options = SweepOptions(
        out=out,
        scheduler=scheduler,
        workers=workers,
        resume=resume,
        figures=not no_figures,
        progress=progress,
        batch=batch,
        command="bristlecrawler " + shlex.join(sys.argv[1:]),
        note=lambda text: typer.echo(f"note: {printable(text)}", err=True),
    )
    summary = run_sweep(study, options)
    if as_json:
        typer.echo(json.dumps(summary))
    else:
        _print_summary(summary)
    return _report_failures(summary)


def _report_failures(summary: dict) -> int:
    """List the failed and lost designs on stderr, the count last; the exit code."""
    from bristlecrawler.studies.runner import LISTED_FAILURES

    bad = summary["failures"]
    if not bad:
        return 0
    for f in bad[:LISTED_FAILURES]:
        typer.echo(printable(f"{f['label']} {f['status']}: {f['error']}"), err=True)
    if len(bad) > LISTED_FAILURES:
        more = len(bad) - LISTED_FAILURES
        typer.echo(f"... and {more} more (study.zarr has every reason)", err=True)
    typer.echo(
        f"error: {len(bad)} of {summary['designs_total']} designs not done "
        f"({summary['designs_failed']} failed, {summary['designs_lost']} lost); the others' "
        f"results are in {printable(summary['output_dir'])}",
        err=True,
    )
    return 1


def _print_summary(summary: dict) -> None:
    from rich.console import Console
    from rich.table import Table

    table = Table(title=f"study {summary['study']} ({summary['model']} model)")
    table.add_column("designs")
    table.add_column("count", justify="right")
    for key in ("total", "done", "failed", "lost", "pending"):
        table.add_row(key, str(summary[f"designs_{key}"]))
    console = Console()
    console.print(table)
    console.print(f"store: {printable(summary['store'])}", markup=False)
    if summary["figures"]:
        console.print(
            f"figures: {printable(str(Path(summary['figures'][0]).parent))}", markup=False
        )
        maps = [f for f in summary["figures"] if Path(f).name.startswith("map_")]
        if maps:
            console.print(f"design map: {printable(maps[0])}", markup=False)


def register(app: typer.Typer) -> None:
    app.command("sweep")(sweep_cmd)
