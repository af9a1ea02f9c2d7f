"""Atomic writes and run folders."""

import json

import pytest

from bristlecrawler.errors import InputError
from bristlecrawler.io import atomic_path, atomic_write_text, prepare_run_dir, write_run_metadata


def test_failed_write_keeps_old_file_and_leaves_no_temporary(tmp_path):
    target = tmp_path / "a.txt"
    atomic_write_text(target, "old")
    with pytest.raises(RuntimeError), atomic_path(target) as tmp:
        tmp.write_text("half-written")
        raise RuntimeError("crash while writing")
    assert target.read_text() == "old"
    assert [p.name for p in tmp_path.iterdir()] == ["a.txt"]


def test_run_dirs_are_unique_and_carry_provenance(tmp_path):
    a = prepare_run_dir(None, "reduced", root=str(tmp_path))
    b = prepare_run_dir(None, "reduced", root=str(tmp_path))
    assert a != b and a.is_dir() and b.is_dir()
    info = write_run_metadata(a, {"k": 0.48}, "bristlecrawler reduced")
    meta = json.loads((a / "meta.json").read_text())
    assert meta["package_version"] == info.version
    assert json.loads((a / "config.json").read_text()) == {"k": 0.48}


def test_output_path_that_is_a_file_is_refused(tmp_path):
    f = tmp_path / "f"
    f.write_text("x")
    with pytest.raises(InputError, match="not a folder"):
        prepare_run_dir(f, "reduced")
