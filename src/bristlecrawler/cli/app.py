"""The ``bristlecrawler`` command.

Each sub-command lives in its own module of this package and is registered here. Heavy
imports (JAX, xarray, matplotlib) happen inside the commands, so ``--help`` stays fast.
Bad input ends with one line on stderr and exit code 2, before any work starts.
"""

from __future__ import annotations

import contextlib
import importlib
import os
import signal
import sys
import warnings

import typer

from bristlecrawler.cli.groups import WholeSummaries
from bristlecrawler.errors import InputError, Interrupted, SolverError, printable

#: The order in which ``--help`` lists the commands: as a user meets them, from the paper's
#: results to a design of one's own, then the tools behind them. A command not named here is
#: listed before ``version``, in the order it was registered.
COMMAND_ORDER = (
    "reproduce",
    "simulate",
    "predict",
    "sweep",
    "drag",
    "reduced",
    "calibrate",
    "analyze",
    "synth-recording",
    "verify",
    "export",
    "crosscheck",
    "scenario",
    "cache",
    "version",
)


class _Commands(WholeSummaries):
    """The top-level group: commands in :data:`COMMAND_ORDER`, each listed with its help's
    whole first sentence."""

    def list_commands(self, ctx) -> list[str]:
        rank = {name: i for i, name in enumerate(COMMAND_ORDER)}
        unlisted = COMMAND_ORDER.index("version") - 0.5
        return sorted(super().list_commands(ctx), key=lambda n: rank.get(n, unlisted))


app = typer.Typer(
    cls=_Commands,
    name="bristlecrawler",
    # click's help is 80 columns wide at most; a wider terminal gets up to 120.
    context_settings={"max_content_width": 120},
    help="Crawlers that move by directional friction: reduced model, FE model, experiments.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
    rich_markup_mode=None,
)


@app.callback()
def _environment() -> None:
    # The variables that name the tool's own files and sizes are checked as options are:
    # a bad one is one line and exit code 2 before any command starts.
    from bristlecrawler._files import cache_limit_bytes
    from bristlecrawler.io.costs import check_costs_env

    check_costs_env()
    try:
        cache_limit_bytes()
    except ValueError as exc:
        raise InputError(str(exc)) from None


@app.command("version")
def version_cmd() -> None:
    """Print the package version and exit."""
    from bristlecrawler import __version__

    typer.echo(__version__)


def _register() -> None:
    from bristlecrawler.cli import (
        cache,
        drag,
        experiment,
        export,
        predict,
        reduced,
        reproduce,
        scenario,
        simulate,
        sweep,
        verify,
    )

    reduced.register(app)
    experiment.register(app)
    verify.register(app)
    simulate.register(app)
    drag.register(app)
    predict.register(app)
    scenario.register(app)
    sweep.register(app)
    reproduce.register(app)
    export.register(app)
    cache.register(app)


_register()


def _fail(message: str, code: int, prefix: str = "error: ") -> None:
    # A message quotes what the user gave (a key, a path, a value): escaped, it cannot
    # send a control sequence to the terminal.
    first = printable(" ".join(str(message).split()))
    typer.echo(f"{prefix}{first}", err=True)
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


def quiet_xla() -> None:
    """Keep XLA's C++ log off stderr: on a busy machine it prints "Very slow compile? If
    you want to file a bug..." alarms that look like errors but only mean a long compile,
    which the commands announce themselves. XLA reads the level when jaxlib loads (so this
    runs before any command imports JAX) and Dask's worker processes inherit it. Failures
    still reach the user as Python exceptions; ``TF_CPP_MIN_LOG_LEVEL=0`` shows the log."""
    os.environ.setdefault("TF_CPP_MIN_LOG_LEVEL", "3")


def main(argv: list[str] | None = None) -> None:
    """Run the CLI; bad input gives one ``error:`` line and exit code 2, no traceback.

    Warnings that libraries (numpy, npTDMS) raise on the way are held back: after a
    failure the error line is all the user sees; after a success each distinct warning is
    one ``warning:`` line. Ctrl-C prints one line saying what was kept, exit code 130.
    """
    quiet_xla()
    with _held_warnings() as held, _sigint_as_interrupted():
        try:
            result = app(args=argv, standalone_mode=False, prog_name="bristlecrawler")
        except _NO_ARGS as exc:
            typer.echo(exc.ctx.get_help())
            raise SystemExit(0) from None
        except _USAGE as exc:
            _fail(exc.format_message(), 2)
        except (*_ABORT, Interrupted, KeyboardInterrupt) as exc:
            _fail(str(exc) if str(exc) else "interrupted: nothing written", 130, "")
        except _EXIT as exc:
            raise SystemExit(exc.exit_code) from None
        except InputError as exc:
            _fail(str(exc), 2)
        except SolverError as exc:
            _fail(f"solver failed: {exc}", 3)
        except FileNotFoundError as exc:
            _fail(f"file not found: {exc.filename}", 2)
        except RecursionError:
            _fail("input nested too deeply", 2)
        except OSError as exc:
            where = f"{exc.filename}: " if exc.filename else ""
            _fail(f"{where}{exc.strerror or exc}", 2 if _is_path_error(exc) else 1)
    _show(held)
    if isinstance(result, int) and result != 0:
        raise SystemExit(result)


def _is_path_error(exc: OSError) -> bool:
    """A path the user gave that cannot be used (rather than, say, a full disk)."""
    import errno

    return exc.errno in (
        errno.EACCES,
        errno.EPERM,
        errno.ENOENT,
        errno.ENOTDIR,
        errno.EISDIR,
        errno.ENAMETOOLONG,
        errno.EEXIST,
        errno.ELOOP,
    )


@contextlib.contextmanager
def _held_warnings():
    with warnings.catch_warnings(record=True) as held:
        yield held


def _show(held: list[warnings.WarningMessage]) -> None:
    seen = set()
    for w in held:
        text = printable(" ".join(str(w.message).split()))
        if text not in seen:
            seen.add(text)
            typer.echo(f"warning: {text}", err=True)


@contextlib.contextmanager
def _sigint_as_interrupted():
    """SIGINT raises :class:`Interrupted`, which Typer does not turn into a silent exit
    130, and which a run folder answers by saying what it kept."""

    def handler(signum, frame):
        raise Interrupted()

    try:
        previous = signal.signal(signal.SIGINT, handler)
    except ValueError:  # not the main thread: leave Ctrl-C alone
        yield
        return
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)


if __name__ == "__main__":  # pragma: no cover
    main(sys.argv[1:])
