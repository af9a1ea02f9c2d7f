"""Input/output at the edges: run folders, atomic writes, NetCDF, VTK.

Configuration files are validated in :mod:`bristlecrawler.scenario`."""

from bristlecrawler.io.atomic import atomic_path, atomic_write_text
from bristlecrawler.io.runs import (
    RunInfo,
    check_out_dir,
    git_revision,
    prepare_run_dir,
    write_run_metadata,
)

__all__ = [
    "RunInfo",
    "atomic_path",
    "atomic_write_text",
    "check_out_dir",
    "git_revision",
    "prepare_run_dir",
    "write_run_metadata",
]
