"""``bristlecrawler export`` and ``crosscheck``: their decks, and bad input refused in one line."""

from __future__ import annotations

import os
import subprocess
import sys

import pytest

from bristlecrawler.export import DECK_FILES


def _run(*args, env=None, cwd=None):
    return subprocess.run(
        [sys.executable, "-m", "bristlecrawler.cli.app", *args],
        capture_output=True,
        text=True,
        env=(os.environ | (env or {})),
        cwd=cwd,
        timeout=300,
    )


def test_export_writes_the_decks_and_their_readme(tmp_path):
    out = tmp_path / "decks"
    r = _run("export", "paper", "--out", str(out), "--set", "bristle.alpha_deg=30")
    assert r.returncode == 0, r.stderr
    assert sorted(p.name for p in out.iterdir()) == sorted(DECK_FILES)
    assert "alpha 30 deg" in (out / "README.md").read_text()
    # An earlier export's folder takes the new decks.
    assert _run("export", "paper", "--out", str(out)).returncode == 0


@pytest.mark.parametrize(
    "args, message",
    [
        (["--format", "vtk"], "--format must be inp"),
        (["--plane", "shell"], "--plane must be stress or strain"),
        (["--set", "bristle.alpha_deg=95"], "alpha"),
        (["--mass-damping", "-1"], "a0 must be a finite number"),
    ],
)
def test_bad_export_input_is_one_line_and_writes_nothing(tmp_path, args, message):
    out = tmp_path / "decks"
    r = _run("export", "paper", "--out", str(out), *args)
    assert r.returncode == 2
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and message in lines[0]
    assert not out.exists()


def test_export_leaves_a_folder_of_other_files_alone(tmp_path):
    (tmp_path / "notes.txt").write_text("mine")
    r = _run("export", "paper", "--out", str(tmp_path))
    assert r.returncode == 2 and "holds other files (notes.txt)" in r.stderr
    assert [p.name for p in tmp_path.iterdir()] == ["notes.txt"]
    assert (tmp_path / "notes.txt").read_text() == "mine"


def test_crosscheck_without_calculix_says_how_to_install_it(tmp_path):
    r = _run(
        "crosscheck",
        "drag",
        "paper",
        "--out",
        str(tmp_path / "x"),
        env={"BRISTLECRAWLER_CCX": str(tmp_path / "no-ccx")},
    )
    assert r.returncode == 2
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and "is not an executable" in lines[0]
    r = _run("crosscheck", "drag", "paper", env={"PATH": str(tmp_path)}, cwd=tmp_path)
    assert r.returncode == 2 and "apt-get install calculix-ccx" in r.stderr
    assert list(tmp_path.iterdir()) == []


def test_the_crosscheck_group_lists_its_commands_whole():
    r = _run("crosscheck", "--help", env={"COLUMNS": "80"})
    assert r.returncode == 0
    assert "in CalculiX (ccx) and in the toolkit." in " ".join(r.stdout.split())
