"""Input/output at the edges: run folders, atomic writes, configuration parsing, NetCDF."""

from bristlecrawler.io.atomic import atomic_path, atomic_write_text
from bristlecrawler.io.config import parse_model
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
    "parse_model",
    "prepare_run_dir",
    "write_run_metadata",
]
