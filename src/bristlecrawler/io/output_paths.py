"""Output paths a user gives: checked before any work, each problem one line.

A path is refused when it is a file where a folder is wanted (or the reverse), lies below a
file, is the current folder, is in a folder that cannot be written, or has a name longer
than the file system takes. Messages shorten very long paths.
"""

from __future__ import annotations

import errno
import os
import re
from collections.abc import Iterable
from pathlib import Path

from bristlecrawler.errors import InputError

#: What a name that becomes part of a folder's name (a scenario's, a study's) may be:
#: letters, digits, ``_``, ``.`` and ``-``, starting with a letter or a digit, so that it
#: can neither climb out of the runs folder (``..``, ``/``) nor hide (a leading dot).
SAFE_NAME = re.compile(r"[A-Za-z0-9][A-Za-z0-9_.-]{0,63}")


#: The names the tool gives its own bookkeeping beside a run's folder and inside it: the
#: lock file and the partial and set-aside folders of a run being written (:mod:`.runs`),
#: a file being written (``.NAME.XXXXXXXX.EXT`` of :mod:`.atomic`, ``.NAME.PID.TID.tmp``
#: of private writes) and a study's store being swapped. A run given one of them as its
#: output would write into another run's files, or have them taken from under it.
RESERVED_NAME = re.compile(
    r"\..+\.lock|\..+\.(partial|old)-[a-z0-9_]{8}|\..+\.[a-z0-9_]{8}\.[A-Za-z0-9]+"
    r"|\..+\.[0-9]+\.[0-9]+\.tmp|\.study\.zarr\..+"
)


def check_not_reserved(path: str | os.PathLike, inside: Iterable[str] = ()) -> None:
    """InputError if a name in ``path`` (as given, or with links followed) is one the tool
    keeps for its own files (:data:`RESERVED_NAME`); below a folder of ``inside`` (real
    paths: the partial folders of the runs this process writes) only the names below it
    count."""
    path = Path(path)
    for shape in (path.absolute(), Path(os.path.realpath(path))):
        parts = shape.parts
        for root in inside:
            if shape.is_relative_to(root):
                parts = shape.relative_to(root).parts or (shape.name,)
        for part in parts:
            if RESERVED_NAME.fullmatch(part):
                raise InputError(
                    f"output path {shown(path)}: {part[:60]!r} is a name the tool keeps for "
                    "its own files (a run being written, a lock); give another --out"
                )


def check_safe_name(name: str) -> str:
    """``name`` if it matches :data:`SAFE_NAME`; ValueError saying what a name may be."""
    if not isinstance(name, str) or not SAFE_NAME.fullmatch(name):
        raise ValueError(
            "a name must be 1 to 64 letters, digits, '_', '.' or '-', starting with a letter "
            f"or a digit (it names the run folder), got {name!r}"[:300]
        )
    return name


def safe_stem(text: str) -> str:
    """A file's stem made a safe name: every other character replaced by ``-``."""
    name = re.sub(r"[^A-Za-z0-9_.-]", "-", text).lstrip("._-")[:64]
    return name or "custom"


def folder_in(root: str | os.PathLike, name: str) -> Path:
    """``root/name``, a run folder made from input: InputError unless ``name`` is one
    plain folder name whose resolved path lies directly inside the resolved ``root``."""
    root = Path(root)
    path = root / name
    inside = Path(os.path.realpath(root))
    if Path(name).name != name or Path(os.path.realpath(path)).parent != inside:
        raise InputError(f"run folder name {name!r} would leave {root}/"[:300])
    return path


def check_new_file(path: str | os.PathLike, replace: bool = False) -> None:
    """InputError unless ``path`` can take a new file: not a folder, not below a file, in a
    writable folder, a name the file system takes, and not an existing file unless
    ``replace``."""
    path = Path(path)
    check_not_reserved(path)
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
