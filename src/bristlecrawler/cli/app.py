"""The ``bristlecrawler`` command.

Each sub-command lives in its own module of this package and is registered here. Heavy
imports (JAX, xarray, matplotlib) happen inside the commands, so ``--help`` stays fast.
Bad input ends with one line on stderr and exit code 2, before any work starts.
"""

from __future__ import annotations

import importlib
import sys

import typer

from bristlecrawler.errors import InputError, SolverError

app = typer.Typer(
    name="bristlecrawler",
    help="Crawlers that move by directional friction: reduced model, FE model, experiments.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
    rich_markup_mode=None,
)


@app.command("version")
def version_cmd() -> None:
    """Print the package version and exit."""
    from bristlecrawler import __version__

    typer.echo(__version__)


def _register() -> None:
    from bristlecrawler.cli import drag, experiment, reduced, scenario, simulate, sweep, verify

    reduced.register(app)
    experiment.register(app)
    verify.register(app)
    simulate.register(app)
    drag.register(app)
    scenario.register(app)
    sweep.register(app)


_register()


def _fail(message: str, code: int) -> None:
    first = " ".join(str(message).split())
    typer.echo(f"error: {first}", err=True)
    raise SystemExit(code)


def _click_exceptions(name: str) -> tuple[type[BaseException], ...]:
    """``name`` from click and from the copy of click that newer Typer versions vendor."""
    found = []
    for module in ("typer._click.exceptions", "click.exceptions"):
        try:
            cls = getattr(importlib.import_module(module), name, None)
        except ImportError:
            continue
        if cls is not None and cls not in found:
            found.append(cls)
    return tuple(found)


_NO_ARGS = _click_exceptions("NoArgsIsHelpError")
_USAGE = _click_exceptions("UsageError")
_ABORT = _click_exceptions("Abort")
_EXIT = _click_exceptions("Exit")


def main(argv: list[str] | None = None) -> None:
    """Run the CLI; bad input gives one ``error:`` line and exit code 2, no traceback."""
    try:
        result = app(args=argv, standalone_mode=False, prog_name="bristlecrawler")
    except _NO_ARGS as exc:
        typer.echo(exc.ctx.get_help())
        raise SystemExit(0) from None
    except _USAGE as exc:
        _fail(exc.format_message(), 2)
    except _ABORT:
        _fail("aborted", 130)
    except _EXIT as exc:
        raise SystemExit(exc.exit_code) from None
    except InputError as exc:
        _fail(str(exc), 2)
    except SolverError as exc:
        _fail(f"solver failed: {exc}", 3)
    except FileNotFoundError as exc:
        _fail(f"file not found: {exc.filename}", 2)
    if isinstance(result, int) and result != 0:
        raise SystemExit(result)


if __name__ == "__main__":  # pragma: no cover
    main(sys.argv[1:])
