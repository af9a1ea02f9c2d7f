"""``bristlecrawler reproduce``: the whole paper in one command, as a report."""

from __future__ import annotations

import shlex
import sys
from pathlib import Path
from typing import Annotated

import typer

from bristlecrawler.cli.options import OutFolder, ShowProgress
from bristlecrawler.errors import printable


def reproduce_cmd(
    out: OutFolder = None,
    quick: Annotated[
        bool,
        typer.Option(
            "--quick",
            help="the short version: one FE cycle, one starting place at alpha = 0, "
            "4 mm drag legs, a reduced-only design study",
        ),
    ] = False,
    as_json: Annotated[
        bool, typer.Option("--json", help="print the paper-versus-toolkit table as JSON")
    ] = False,
    open_report: Annotated[
        bool, typer.Option("--open", help="open report.html in the web browser when done")
    ] = False,
    recording: Annotated[
        Path | None,
        typer.Option(
            "--recording",
            help="CSV or TDMS recording of the prototype to analyse (columns time_s, "
            "left_mm, right_mm) [default: the toolkit's synthetic recording]",
        ),
    ] = None,
    progress: ShowProgress = None,
) -> int:
    """Reproduce the paper's results and write a report of them beside the paper's.

    The parts, in order: the experiments, the FE model at alpha = pi/4 and 0, the reduced
    model and its calibration, a drag test, a design study; then the table paper versus
    bristlecrawler.

    Writes report.html (self-contained), report.md, table.json, the figures and the
    animation, config.json and meta.json. Exit code 1 if a part failed (the report says
    which and why), 2 on bad input (nothing written).
    """
    from bristlecrawler.jobs.reproduce import ReproduceOptions, run_reproduce

    opts = ReproduceOptions(
        out=out,
        quick=quick,
        recording=recording,
        progress=False if as_json and progress is None else progress,
        command="bristlecrawler " + shlex.join(sys.argv[1:]),
    )
    run = run_reproduce(opts)
    for note in run.notes:
        typer.echo(f"warning: {printable(note)}", err=True)
    for name in run.failed:
        typer.echo(f"error: part {name} failed: {printable(run.results[name].error)}", err=True)
    if as_json:
        from bristlecrawler.io.jsonio import dumps_strict

        typer.echo(dumps_strict(run.table_json()))
    else:
        _print_table(run)
    if open_report:
        import webbrowser

        webbrowser.open((run.out_dir / "report.html").resolve().as_uri())
    return 1 if run.failed else 0


def _print_table(run) -> None:
    from rich.console import Console
    from rich.table import Table

    table = Table(title="paper versus bristlecrawler")
    for col in ("quantity", "paper", "bristlecrawler", "difference", "verdict"):
        table.add_column(col, justify="left" if col in ("quantity", "verdict") else "right")
    for r in run.rows:
        ours = r.ours_text or ("" if r.ours is None else f"{r.ours:.3f}")
        diff = "" if r.difference is None else f"{r.difference:+.3f}"
        table.add_row(f"{r.quantity} ({r.unit})", r.paper_text, ours, diff, r.verdict)
    console = Console()
    console.print(table)
    console.print(f"report: {printable(str(run.out_dir / 'report.html'))}", markup=False)


def register(app: typer.Typer) -> None:
    app.command("reproduce")(reproduce_cmd)
