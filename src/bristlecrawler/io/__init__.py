"""Input/output at the edges: run folders, atomic writes, configuration parsing, NetCDF."""

from bristlecrawler.io.atomic import atomic_path, atomic_write_text
from bristlecrawler.io.config import parse_model
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
    "parse_model",
    "run_status",
]
