"""``bristlecrawler predict``: the reduced models' advance and work for a scenario."""

from __future__ import annotations

from typing import Annotated

import typer

from bristlecrawler.cli.options import JsonSummary
from bristlecrawler.results import keys


def predict_cmd(
    scenario: Annotated[
        str, typer.Argument(help="shipped scenario (paper, paper-vertical) or a TOML file")
    ] = "paper",
    assign: Annotated[
        list[str] | None,
        typer.Option("--set", help="override a scenario value, section.key=value; repeatable"),
    ] = None,
    cycles: Annotated[
        int | None,
        typer.Option("--cycles", help="number of strokes [default: the scenario's]"),
    ] = None,
    drag: Annotated[
        bool,
        typer.Option(
            "--drag/--no-drag",
            help="run (or read from the cache) the FE drag test that the texture-law and "
            "paper's models need; --no-drag gives the bristled model alone, in seconds",
        ),
    ] = True,
    bristled: Annotated[
        bool,
        typer.Option(
            "--bristled/--no-bristled",
            help="run the bristled model (the default model, seconds to a minute); "
            "--no-bristled gives the drag-test models alone",
        ),
    ] = True,
    as_json: JsonSummary = False,
) -> None:
    """Predict a design's advance and work with the reduced models, before any FE run.

    The bristled model (elastic bristles on the real grooves, the body in equilibrium; no
    FE) is the default and needs seconds. Beside it, unless --no-drag: runs a drag test
    of the scenario's bristle over its substrate (minutes; kept in the drag cache:
    $BRISTLECRAWLER_DRAG_CACHE, else $XDG_CACHE_HOME/bristlecrawler/drag, else
    ~/.cache/bristlecrawler/drag), then the reduced crawler on the texture law it gives
    and the paper's reduced model with its k, F_p, F_n. Each model's line says what it
    assumed; the paper's model is not run where the drag test finds F_n < F_p; where the
    two differ by more than a pitch per cycle, a note says which one the FE crawler has
    checked on such designs.
    """
    from bristlecrawler.errors import InputError
    from bristlecrawler.fe import enable_compilation_cache
    from bristlecrawler.jobs.predict import run_predict
    from bristlecrawler.scenario.load import apply_overrides, load_scenario

    if cycles is not None and not 1 <= cycles <= 1000:
        raise InputError(f"--cycles must be between 1 and 1000, got {cycles}")
    sc = load_scenario(scenario)
    if assign:
        sc = apply_overrides(sc, list(assign))
    enable_compilation_cache()
    result = run_predict(
        sc, cycles, progress=None if not as_json else False, drag=drag, bristled=bristled
    )
    result["changes"] = list(assign or [])
    if as_json:
        from bristlecrawler.io.jsonio import dumps_strict

        typer.echo(dumps_strict(result))
        return
    _print(result)


def _title(r: dict) -> str:
    """What was run: the scenario and the changes made to it."""
    design = r["scenario"]
    if r["changes"]:
        design += " with " + ", ".join(r["changes"])
    return f"{design}: reduced models, {r['cycles']} cycles"


def _print(r: dict) -> None:
    from rich.console import Console
    from rich.table import Table

    from bristlecrawler.results.metrics import RunMetrics

    table = Table(title=_title(r))
    table.add_column("model")
    table.add_column("advance per cycle (mm)", justify="right")
    table.add_column("net advance (mm)", justify="right")
    table.add_column("work (mJ)", justify="right")
    for name, model in r["models"].items():
        label = model["label"] + (" [default]" if name == r["default"] else "")
        if r[name] is None:
            table.add_row(label, "not run (below)", "", "")
            continue
        m = RunMetrics.from_dict(r[name])
        per = ", ".join(f"{a:.2f}" for a in m.advance_per_cycle)
        table.add_row(label, per, f"{m.net_advance:.3f}", f"{m.work:.3f}")
    console = Console()
    say = lambda text: console.print(text, markup=False, highlight=False)  # noqa: E731
    say(table)
    d = r["drag"]
    if d is not None:
        where = "from the drag cache" if d["cached"] else "run now"
        say(
            f"FE drag test of one bristle ({where}): k = {d[keys.K_N_PER_MM]:.3f} N/mm, "
            f"F_p = {d[keys.FP_N]:.3f} N, F_n = {d[keys.FN_N]:.3f} N, pitch {d['pitch_mm']:g} mm"
        )
    for model in r["models"].values():
        if model["assumes"]:
            say(f"{model['label']} assumes: {model['assumes']}")
    for model in r["models"].values():
        say(f"{model['label']} checked against the FE crawler: {model['checked']}")
    for model in r["models"].values():
        if model["not_run"]:
            say(f"{model['label']} not applicable: {model['not_run']}")
    if r["disagreement"]:
        say(f"which to trust: {r['disagreement']}")


def register(app: typer.Typer) -> None:
    app.command("predict")(predict_cmd)
