"""``bristlecrawler export`` and ``bristlecrawler crosscheck drag``: decks for ABAQUS and
CalculiX, and the drag test run in CalculiX beside the toolkit's own."""

from __future__ import annotations

import shlex
import sys
from pathlib import Path
from typing import Annotated

import typer

from bristlecrawler.cli.groups import WholeSummaries
from bristlecrawler.cli.options import JsonSummary, OutFolder, ReplaceRun, ShowProgress
from bristlecrawler.errors import printable

ScenarioArg = Annotated[
    str, typer.Argument(help="shipped scenario (paper, paper-vertical) or a TOML file")
]
Assign = Annotated[
    list[str] | None,
    typer.Option("--set", help="override a scenario value, section.key=value; repeatable"),
]
Plane = Annotated[
    str,
    typer.Option(
        "--plane",
        help="the continuum bristle: stress (narrow, the beam's E) or strain (wide plate)",
    ),
]


def _scenario(scenario: str, assign: list[str] | None):
    from bristlecrawler.scenario.load import apply_overrides, load_scenario

    sc = load_scenario(scenario)
    return apply_overrides(sc, list(assign)) if assign else sc


def _plane(plane: str) -> str:
    from bristlecrawler.errors import InputError

    if plane not in ("stress", "strain"):
        raise InputError(f"--plane must be stress or strain, got {plane!r}")
    return plane


def export_cmd(
    scenario: ScenarioArg = "paper",
    fmt: Annotated[
        str, typer.Option("--format", help="deck format: inp (ABAQUS, CalculiX)")
    ] = "inp",
    out: Annotated[Path, typer.Option("--out", help="folder for the decks (new or empty)")] = Path(
        "decks"
    ),
    plane: Plane = "stress",
    a0: Annotated[
        float | None,
        typer.Option(
            "--mass-damping",
            help="Rayleigh mass coefficient a0, 1/s (a run's rayleigh_a0_per_s) [default: "
            "an estimate at the bristle's first bending frequency]",
        ),
    ] = None,
    assign: Assign = None,
) -> None:
    """Write a design as ABAQUS/CalculiX input decks: its drag test and its crawler.

    The drag test as a continuum (CalculiX and ABAQUS) and with the paper's B21 beams
    (ABAQUS), the crawler as the paper's model (ABAQUS), and a README saying which
    keywords CalculiX reads. Writes into --out (a new or empty folder, or an earlier
    export's)."""
    from bristlecrawler.errors import InputError
    from bristlecrawler.export import ContinuumOptions, decks, write_decks
    from bristlecrawler.scenario.convert import to_spec

    if fmt != "inp":
        raise InputError(f"--format must be inp (the ABAQUS dialect CalculiX reads), got {fmt!r}")
    spec = to_spec(_scenario(scenario, assign))
    texts = decks(spec, options=ContinuumOptions(plane=_plane(plane)), a0=a0)
    _check_folder(out, texts)
    out.mkdir(parents=True, exist_ok=True)
    for path in write_decks(out, texts):
        typer.echo(printable(str(path)))


def _check_folder(out: Path, texts: dict[str, str]) -> None:
    """The decks go into a new or empty folder, or replace an earlier export's decks;
    anything else there stays untouched and is refused."""
    from bristlecrawler.errors import InputError

    if out.is_symlink() or (out.exists() and not out.is_dir()):
        raise InputError(f"--out {out} is not a folder")
    if not out.exists():
        if not out.parent.exists():
            raise InputError(f"--out {out}: its parent folder does not exist")
        return
    other = sorted(p.name for p in out.iterdir() if p.name not in texts)
    if other:
        shown = ", ".join(other[:3]) + (", ..." if len(other) > 3 else "")
        raise InputError(f"--out {out} holds other files ({shown}): give a new or empty folder")
    links = [p.name for p in out.iterdir() if p.is_symlink() or not p.is_file()]
    if links:
        raise InputError(f"--out {out}: {links[0]} is not a regular file; remove it first")


crosscheck_app = typer.Typer(
    cls=WholeSummaries,
    help="Run a design's test in another FE code and compare it with the toolkit's.",
    no_args_is_help=True,
)


@crosscheck_app.command("drag")
def crosscheck_drag_cmd(
    scenario: ScenarioArg = "paper",
    plane: Plane = "stress",
    assign: Assign = None,
    out: OutFolder = None,
    replace: ReplaceRun = False,
    as_json: JsonSummary = False,
    progress: ShowProgress = None,
) -> None:
    """The drag test of the design's first bristle in CalculiX (ccx) and in the toolkit.

    Two legs of one pitch along the grain: on a flat at the lands' level (the stiffness
    before sliding, the sliding force mu N) and, on grooves, from a groove's middle (the
    peak force at its wall). Writes crosscheck.json, crosscheck.md, crosscheck.png and
    CalculiX's files; minutes (two toolkit drag tests, compiled on a first run).
    """
    from bristlecrawler.export.ccx import find_ccx
    from bristlecrawler.fe import enable_compilation_cache
    from bristlecrawler.io.runs import check_out_dir
    from bristlecrawler.jobs.crosscheck import prepare, run_crosscheck
    from bristlecrawler.jobs.simulate import summary_json
    from bristlecrawler.scenario.convert import to_spec

    sc = _scenario(scenario, assign)
    prepare(to_spec(sc), _plane(plane))  # bad input: one line, before any work
    find_ccx()
    check_out_dir(out, replace)
    enable_compilation_cache()
    run = run_crosscheck(
        sc,
        plane=plane,
        out=out,
        progress=False if as_json else progress,
        command="bristlecrawler " + shlex.join(sys.argv[1:]),
        replace=replace,
    )
    if as_json:
        typer.echo(summary_json({"rows": [r.to_dict() for r in run.rows], **run.facts}))
        return
    _print(run)


def _print(run) -> None:
    from rich.console import Console
    from rich.table import Table

    table = Table(title="drag test: bristlecrawler against CalculiX")
    for col in ("quantity", "bristlecrawler", "CalculiX", "difference", "expected"):
        table.add_column(col, justify="left" if col == "quantity" else "right")
    for r in run.rows:
        exp = "" if r.expected != r.expected else f"{r.expected:.4g}"
        diff = "" if r.difference != r.difference else f"{100 * r.difference:+.1f} %"
        table.add_row(
            f"{r.quantity} ({r.unit})", f"{r.toolkit:.4g}", f"{r.calculix:.4g}", diff, exp
        )
    console = Console()
    console.print(table)
    if not run.facts["calculix_complete"]:
        console.print(
            f"CalculiX stopped before the end of the path: {run.facts['calculix_stopped']}"
        )
    console.print(f"results in {printable(str(run.out_dir))}", markup=False)


def register(app: typer.Typer) -> None:
    app.command("export")(export_cmd)
    app.add_typer(crosscheck_app, name="crosscheck")
