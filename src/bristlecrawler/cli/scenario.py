"""``bristlecrawler scenario``: the shipped scenarios and every key a scenario file takes."""

from __future__ import annotations

import json
from typing import Annotated

import typer

from bristlecrawler.cli.groups import WholeSummaries
from bristlecrawler.errors import printable

scenario_app = typer.Typer(
    cls=WholeSummaries,
    name="scenario",
    help="Shipped scenarios of the FE crawler and the keys of a scenario file.",
    no_args_is_help=True,
    add_completion=False,
    rich_markup_mode=None,
)


@scenario_app.command("list")
def list_cmd() -> None:
    """List the shipped scenarios with their descriptions."""
    from bristlecrawler.scenario.load import available_scenarios, load_scenario

    for name in available_scenarios():
        typer.echo(f"{name:16s} {load_scenario(name).description}")


@scenario_app.command("show")
def show_cmd(
    scenario: Annotated[
        str, typer.Argument(help="shipped scenario (paper, paper-vertical) or a TOML file")
    ],
    resolved: Annotated[
        bool,
        typer.Option(
            "--resolved",
            help="print every key with the value a run would use (base scenario and "
            "defaults filled in) instead of the file as written",
        ),
    ] = False,
) -> None:
    """Print a scenario as TOML: a shipped one as it is shipped (with its comments), to copy
    and edit, or with --resolved every value a run would use."""
    from pathlib import Path

    from bristlecrawler.scenario.load import load_scenario, shipped_scenario_text

    sc = load_scenario(scenario)  # checks the file (and its base) first
    if resolved:
        from bristlecrawler.scenario.keys import scenario_toml

        typer.echo(scenario_toml(sc), nl=False)
    elif Path(scenario).is_file():
        typer.echo(printable(Path(scenario).read_text(encoding="utf-8"), keep="\n\t"), nl=False)
    else:
        typer.echo(shipped_scenario_text(scenario), nl=False)


@scenario_app.command("keys")
def keys_cmd(
    markdown: Annotated[
        bool, typer.Option("--markdown", help="Markdown tables (the documentation's reference)")
    ] = False,
    as_json: Annotated[bool, typer.Option("--json", help="a JSON list on stdout")] = False,
) -> None:
    """List every key of a scenario file: unit, default and the `paper` scenario's value
    (marked * where it differs from the default), and whether it is structural (a design
    that differs in it needs its own compiled program)."""
    from bristlecrawler.scenario.keys import NA, differs, keys_markdown, scenario_keys, toml_value

    keys = scenario_keys()
    if markdown:
        typer.echo(keys_markdown(keys), nl=False)
        return
    if as_json:
        rows = [
            {
                "key": k.key,
                "substrate_kind": k.kind or None,
                "type": k.type,
                "unit": k.unit,
                "default": None if k.required else toml_value(k.default),
                "required": k.required,
                "paper": None if k.paper is NA else toml_value(k.paper),
                "meaning": k.meaning,
                "structural": k.structural,
            }
            for k in keys
        ]
        typer.echo(json.dumps(rows, indent=1))
        return
    from rich.console import Console
    from rich.table import Table

    table = Table(
        title="scenario keys (* the paper scenario differs from the default; "
        "S: structural, a design that differs in it needs its own compiled program)"
    )
    for col in ("key", "unit", "default", "paper", "meaning", "S"):
        table.add_column(col, overflow="fold")
    for k in keys:
        name = f"{k.key} ({k.kind})" if k.kind else k.key
        paper = "" if k.paper is NA else _short(toml_value(k.paper)) + (" *" if differs(k) else "")
        default = "required" if k.required else toml_value(k.default)
        table.add_row(name, k.unit, default, paper, k.meaning, "S" if k.structural else "")
    Console().print(table)


def _short(text: str, n: int = 24) -> str:
    return text if len(text) <= n else text[: n - 3] + '..."'


def register(app: typer.Typer) -> None:
    app.add_typer(scenario_app, name="scenario")
