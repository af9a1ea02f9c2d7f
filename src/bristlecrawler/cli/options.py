"""Options shared by the commands that write a run folder (one help text each)."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

#: ``--out``: the run folder.
OutFolder = Annotated[Path | None, typer.Option("--out", help="output folder [default: runs/<id>]")]

#: ``--replace``: a finished run replaces the one in ``--out``.
ReplaceRun = Annotated[
    bool,
    typer.Option(
        "--replace", help="replace the run (complete or not) in --out once this one is done"
    ),
]

#: ``--json``: a JSON summary on stdout.
JsonSummary = Annotated[bool, typer.Option("--json", help="print a JSON summary on stdout")]

#: ``--progress/--no-progress``: progress on stderr.
ShowProgress = Annotated[
    bool | None,
    typer.Option(
        "--progress/--no-progress",
        help="progress on stderr [default: bars on a terminal, else one line per stage]",
    ),
]
