"""Input/output at the edges: run folders, atomic writes, strict JSON, NetCDF, VTK.

Configuration files are validated in :mod:`bristlecrawler.scenario`."""

from bristlecrawler.io.atomic import atomic_path, atomic_write_text
from bristlecrawler.io.jsonio import dumps_strict
from bristlecrawler.io.provenance import RunInfo, git_revision
from bristlecrawler.io.runs import RunFolder, check_out_dir, claim_run_dir, run_status

__all__ = [
    "RunFolder",
    "RunInfo",
    "atomic_path",
    "atomic_write_text",
    "check_out_dir",
    "claim_run_dir",
    "dumps_strict",
    "git_revision",
    "run_status",
]
