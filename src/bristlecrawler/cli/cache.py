"""``bristlecrawler cache``: what the tool keeps outside its run folders, and emptying the
compilation caches."""

from __future__ import annotations

import json
import os

import typer

from bristlecrawler.cli.groups import WholeSummaries
from bristlecrawler.cli.options import JsonSummary
from bristlecrawler.errors import printable

cache_app = typer.Typer(
    cls=WholeSummaries,
    name="cache",
    help="The compiled programs and the other files the tool keeps between runs.",
    no_args_is_help=True,
    add_completion=False,
    rich_markup_mode=None,
)


def _mb(size: int) -> str:
    return f"{size / 2**20:.1f} MB"


def _files_in(folder) -> tuple[int, int]:
    """Regular files directly in ``folder`` and their bytes (0, 0 where it is absent)."""
    count = size = 0
    try:
        listing = list(os.scandir(folder))
    except OSError:
        return 0, 0
    for e in listing:
        try:
            if e.is_file(follow_symlinks=False):
                count, size = count + 1, size + e.stat(follow_symlinks=False).st_size
        except OSError:
            continue
    return count, size


def _info() -> dict:
    from bristlecrawler._files import cache_limit_bytes
    from bristlecrawler.fe.cache import cache_folder
    from bristlecrawler.fe.cache_size import cache_usage
    from bristlecrawler.fe.program_store import key_path
    from bristlecrawler.io.costs import costs_off, costs_path
    from bristlecrawler.jobs.predict import cache_folder as drag_folder

    folder = cache_folder()
    usage = cache_usage(folder) if folder is not None else {"programs": (0, 0), "jax": (0, 0)}
    drag = drag_folder()
    n_drag, drag_bytes = _files_in(drag)
    return {
        "compilation_cache": None if folder is None else str(folder),
        "stored_programs": {"entries": usage["programs"][0], "bytes": usage["programs"][1]},
        "jax_programs": {"entries": usage["jax"][0], "bytes": usage["jax"][1]},
        "limit_bytes": cache_limit_bytes(),
        "cache_key": str(key_path()),
        "drag_cache": str(drag),
        "drag_summaries": {"entries": n_drag, "bytes": drag_bytes},
        "costs_file": None if costs_off() else str(costs_path()),
    }


@cache_app.command("info")
def info_cmd(as_json: JsonSummary = False) -> None:
    """Show where the caches are, what they hold and the compiled programs' size limit
    (BRISTLECRAWLER_CACHE_MB)."""
    info = _info()
    if as_json:
        typer.echo(json.dumps(info, indent=1))
        return
    shown = {k: printable(v) if isinstance(v, str) else v for k, v in info.items()}
    programs, jax = info["stored_programs"], info["jax_programs"]
    held = programs["bytes"] + jax["bytes"]
    if shown["compilation_cache"] is None:
        typer.echo("compiled programs: off (BRISTLECRAWLER_NO_JAX_CACHE)")
    else:
        typer.echo(f"compiled programs: {shown['compilation_cache']}")
        typer.echo(
            f"  {_mb(held)} of at most {_mb(info['limit_bytes'])} (BRISTLECRAWLER_CACHE_MB): "
            f"{programs['entries']} stored programs ({_mb(programs['bytes'])}), "
            f"{jax['entries']} of JAX's ({_mb(jax['bytes'])}); the least recently used go first"
        )
    typer.echo(f"  signed with the key in {shown['cache_key']}")
    drag = info["drag_summaries"]
    typer.echo(
        f"drag summaries: {shown['drag_cache']} ({drag['entries']} entries, {_mb(drag['bytes'])})"
    )
    costs = shown["costs_file"] or "off (BRISTLECRAWLER_NO_COSTS)"
    typer.echo(f"measured costs: {costs}")


@cache_app.command("clear")
def clear_cmd() -> None:
    """Remove the compiled programs (stored and JAX's): the next run compiles them again.
    The drag summaries, the measured costs and the key stay."""
    from bristlecrawler.fe.cache import cache_folder
    from bristlecrawler.fe.cache_size import cache_usage, clear

    folder = cache_folder()
    if folder is None:
        typer.echo("compiled programs: off (BRISTLECRAWLER_NO_JAX_CACHE); nothing to clear")
        return
    usage = cache_usage(folder)
    entries = usage["programs"][0] + usage["jax"][0]
    removed = clear(folder)
    typer.echo(
        f"removed {entries} compiled programs ({_mb(removed)}) from {printable(str(folder))}"
    )


def register(app: typer.Typer) -> None:
    app.add_typer(cache_app, name="cache")
