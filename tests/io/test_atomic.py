"""Atomic writes and run folders."""

import json

import pytest

from bristlecrawler.errors import InputError
from bristlecrawler.io import atomic_path, atomic_write_text, claim_run_dir


def test_failed_write_keeps_old_file_and_leaves_no_temporary(tmp_path):
    target = tmp_path / "a.txt"
    atomic_write_text(target, "old")
    with pytest.raises(RuntimeError), atomic_path(target) as tmp:
        tmp.write_text("half-written")
        raise RuntimeError("crash while writing")
    assert target.read_text() == "old"
    assert [p.name for p in tmp_path.iterdir()] == ["a.txt"]


def test_run_dirs_are_unique_and_carry_provenance(tmp_path):
    with claim_run_dir(None, "reduced", root=tmp_path) as a:
        info = a.write_metadata({"k": 0.48}, "bristlecrawler reduced")
        with claim_run_dir(None, "reduced", root=tmp_path) as b:
            b.write_metadata({}, "")
    assert a.target != b.target and a.target.is_dir() and b.target.is_dir()
    meta = json.loads((a.target / "meta.json").read_text())
    assert meta["package_version"] == info.version and meta["status"] == "complete"
    assert json.loads((a.target / "config.json").read_text()) == {"k": 0.48}
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted([a.target.name, b.target.name])


def test_output_path_that_is_a_file_is_refused(tmp_path):
    f = tmp_path / "f"
    f.write_text("x")
    with pytest.raises(InputError, match="not a folder"):
        claim_run_dir(f, "reduced")
