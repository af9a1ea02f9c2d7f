"""Exceptions shared by every layer.

User input is validated at the edge and refused with :class:`InputError`, whose message is a
single line naming the offending parameter; the CLI prints it and exits with code 2.
Solvers report failures as values (a status and a message) and raise :class:`SolverError`
only when the caller asked them to throw.
"""

from __future__ import annotations

import math


class BristlecrawlerError(Exception):
    """Base class of the package's own errors."""


class InputError(BristlecrawlerError, ValueError):
    """Bad user input (parameter, configuration file, data file). One line, names the problem."""


class SolverError(BristlecrawlerError, RuntimeError):
    """A solver could not produce a trustworthy answer; the message says where and why."""


class Interrupted(BaseException):
    """The user interrupted a command (Ctrl-C); the message says what was kept.

    A BaseException, like KeyboardInterrupt, so that ``except Exception`` does not swallow
    it; the CLI raises it from its SIGINT handler, prints its message and exits with 130.
    """


def printable(text: str, keep: str = "") -> str:
    """``text`` as it may reach a terminal: every character that is not printable (the
    escape that starts a terminal's control sequence, a bell, a carriage return, a
    right-to-left override, ...) written as its Python escape, ``\\x1b``, so that input
    can neither retitle, recolour nor rewrite the user's terminal. Characters in ``keep``
    (a newline, a tab) pass as they are."""
    return "".join(c if c.isprintable() or c in keep else repr(c)[1:-1] for c in text)


def positive(name: str, value: float) -> float:
    """``value`` as a float; InputError naming ``name`` unless it is finite and > 0."""
    value = float(value)
    if not math.isfinite(value) or value <= 0.0:
        raise InputError(f"{name} must be a positive finite number, got {value!r}")
    return value
