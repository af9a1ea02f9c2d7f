"""Output paths a user gives: checked before any work, each problem one line.

A path is refused when it is a file where a folder is wanted (or the reverse), lies below a
file, is the current folder, is in a folder that cannot be written, or has a name longer
than the file system takes. Messages shorten very long paths.
"""

from __future__ import annotations

import errno
import os
from pathlib import Path

from bristlecrawler.errors import InputError


def check_new_file(path: str | os.PathLike, replace: bool = False) -> None:
    """InputError unless ``path`` can take a new file: not a folder, not below a file, in a
    writable folder, a name the file system takes, and not an existing file unless
    ``replace``."""
    path = Path(path)
    try:
        if path.is_dir():
            raise InputError(f"output file {shown(path)} is a folder")
        check_parent(path)
        if path.exists() and not replace:
            raise InputError(f"output file {shown(path)} exists; give --replace to overwrite it")
    except OSError as exc:
        raise InputError(f"cannot write {shown(path)}: {why(exc)}") from None


def shown(path: Path) -> str:
    """``path`` for a one-line message: a very long one shortened."""
    text = str(path)
    return text if len(text) <= 100 else f"{text[:60]}...{text[-20:]}"


def why(exc: OSError) -> str:
    """What went wrong, in a few words."""
    return "name too long" if exc.errno == errno.ENAMETOOLONG else str(exc.strerror or exc)


def output_folder(path: Path) -> Path:
    """The folder a run is to be written to (a link followed); InputError if ``path``
    cannot be one."""
    try:
        return _resolved_folder(path)
    except OSError as exc:
        raise InputError(f"cannot use output folder {shown(path)}: {why(exc)}") from None


def _resolved_folder(path: Path) -> Path:
    if path.name in ("", ".."):  # ".", "..", "/": the folder's own name is needed
        path = Path(os.path.abspath(path))
    if Path.cwd().is_relative_to(path.absolute()):
        raise InputError(
            f"output folder {path} is the current folder or holds it; give a folder for "
            "the run, e.g. --out runs/my-run"
        )
    if path.is_symlink():
        if not path.exists():
            raise InputError(f"output path {path} is a link to nothing")
        path = path.resolve()
    if path.exists() and not path.is_dir():
        raise InputError(f"output path {path} exists and is not a folder")
    return path


def check_parent(path: Path) -> None:
    """InputError unless ``path`` (file or folder) can be created: its nearest existing
    ancestor is a writable folder and no part of the name is too long."""
    parent = path.absolute().parent
    try:
        while not parent.exists():
            parent = parent.parent
    except OSError as exc:
        raise InputError(f"cannot use {shown(path)}: {why(exc)}") from None
    if not parent.is_dir():
        raise InputError(f"cannot create {shown(path)}: {shown(parent)} is not a folder")
    if not os.access(parent, os.W_OK | os.X_OK):
        raise InputError(f"cannot create {shown(path)}: {shown(parent)} is not writable")
    limit = os.pathconf(parent, "PC_NAME_MAX") if hasattr(os, "pathconf") else 255
    # The partial folder's name is the longest one the run creates beside the target.
    too_long = [p for p in path.parts if len(os.fsencode(p)) + 18 > limit]
    if too_long:
        raise InputError(
            f"a name in {shown(path)} is too long for the file system (at most "
            f"{limit - 18} bytes for an output folder)"
        )
