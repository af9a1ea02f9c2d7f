"""Run folders as transactions: claimed before the solve, complete or absent, never mixed.

The race, kill and Ctrl-C cases run real ``bristlecrawler`` processes on the reduced model
(about a second of solving each); the rest run in-process.
"""

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from bristlecrawler.errors import InputError, Interrupted
from bristlecrawler.io.runs import claim_run_dir, run_status

SRC = str(Path(__file__).resolve().parents[2] / "src")


def _strict(text: str):
    def refuse(name):
        raise ValueError(f"non-standard JSON constant {name}")

    return json.loads(text, parse_constant=refuse)


def _cli(*args: str, cwd: Path) -> subprocess.Popen:
    env = os.environ | {"PYTHONPATH": SRC + os.pathsep + os.environ.get("PYTHONPATH", "")}
    return subprocess.Popen(
        [sys.executable, "-m", "bristlecrawler.cli.app", *args],
        cwd=cwd,
        env=env,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )


def _wait_for(predicate, timeout=120.0):
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        if predicate():
            return True
        time.sleep(0.02)
    return False


def _partials(parent: Path, name: str = "o") -> list[Path]:
    return sorted(parent.glob(f".{name}.partial-*"))


def _tree(root: Path) -> dict[str, bytes]:
    return {
        str(p.relative_to(root)): p.read_bytes() if p.is_file() else b"<dir>"
        for p in sorted(root.rglob("*"))
    }


@pytest.mark.slow
def test_two_runs_into_one_folder_at_once_never_mix(tmp_path):
    """Both start together: one writes the folder, the other is refused at once (exit 2,
    one line) and the folder's configuration and results belong to the same run."""
    a = _cli(
        "reduced", "--fp", "0.40", "--cycles", "20", "--no-figures", "--out", "o", cwd=tmp_path
    )
    b = _cli(
        "reduced", "--fp", "0.30", "--cycles", "20", "--no-figures", "--out", "o", cwd=tmp_path
    )
    results = [(p.wait(timeout=300), p.stderr.read()) for p in (a, b)]
    codes = sorted(code for code, _ in results)
    assert codes == [0, 2], results
    err = next(e for c, e in results if c == 2)
    assert err.startswith("error: output folder o ") and err.count("\n") == 1
    assert "being written by another run" in err or "already holds a run" in err
    config = _strict((tmp_path / "o" / "config.json").read_text())
    summary = _strict((tmp_path / "o" / "summary.json").read_text())
    assert summary["fp_over_k_mm"] == pytest.approx(config["fp"] / config["k"])
    assert _strict((tmp_path / "o" / "meta.json").read_text())["status"] == "complete"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["o"]  # no partial folder, no lock


def test_a_killed_run_leaves_no_folder_and_does_not_block_the_rerun(tmp_path, run_cli):
    proc = _cli("reduced", "--cycles", "400", "--no-figures", "--out", "o", cwd=tmp_path)
    try:
        assert _wait_for(lambda: _partials(tmp_path)), "the run never claimed its folder"
        proc.send_signal(signal.SIGKILL)
        proc.wait(timeout=60)
    finally:
        proc.kill()
    assert proc.returncode == -signal.SIGKILL
    assert not (tmp_path / "o").exists()  # nothing half-written under the name asked for
    code, _out, err = run_cli(["reduced", "--json", "--no-figures", "--out", str(tmp_path / "o")])
    assert code == 0, err
    assert "removed" in err and "killed" in err
    assert run_status(tmp_path / "o") == "complete"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["o"]


@pytest.mark.slow
def test_ctrl_c_during_the_solve_says_nothing_was_written(tmp_path):
    # Long enough (seconds of solving) that the signal lands in the solve on a loaded
    # machine too, where the claim is seen late.
    proc = _cli("reduced", "--cycles", "2000", "--no-figures", "--out", "o", cwd=tmp_path)
    try:
        assert _wait_for(lambda: _partials(tmp_path)), "the run never claimed its folder"
        time.sleep(0.3)  # into the solve
        proc.send_signal(signal.SIGINT)
        _, err = proc.communicate(timeout=60)
    finally:
        proc.kill()
    assert proc.returncode == 130
    assert err == "interrupted: nothing written to o\n"
    assert list(tmp_path.iterdir()) == []


def _interrupt_in_figures(monkeypatch, exc=Interrupted):
    def boom(*args, **kwargs):
        raise exc()

    monkeypatch.setattr("bristlecrawler.viz.reduced.save_figure", boom)


def test_ctrl_c_after_the_results_keeps_them_marked_incomplete(tmp_path, run_cli, monkeypatch):
    """Interrupted while drawing figures: reduced.nc is kept, meta.json says
    "interrupted", a rerun is refused as incomplete and --replace replaces it."""
    out = tmp_path / "o"
    _interrupt_in_figures(monkeypatch)
    code, _, err = run_cli(["reduced", "--out", str(out)])
    assert code == 130 and err.count("\n") == 1
    assert err.startswith(f"interrupted: kept {out} (config.json, meta.json, reduced.nc)")
    assert run_status(out) == "interrupted"
    monkeypatch.undo()
    code, _, err = run_cli(["reduced", "--no-figures", "--out", str(out)])
    assert code == 2 and "incomplete run (status: interrupted)" in err and "--replace" in err
    code, _, err = run_cli(["reduced", "--no-figures", "--replace", "--json", "--out", str(out)])
    assert code == 0, err
    assert run_status(out) == "complete" and (out / "summary.json").exists()


def test_ctrl_c_while_replacing_keeps_the_old_run(tmp_path, run_cli, monkeypatch):
    out = tmp_path / "o"
    assert run_cli(["reduced", "--json", "--no-figures", "--out", str(out)])[0] == 0
    before = _tree(tmp_path)
    _interrupt_in_figures(monkeypatch)
    code, _, err = run_cli(["reduced", "--replace", "--fp", "0.3", "--out", str(out)])
    assert code == 130 and err == f"interrupted: {out} left as it was, nothing of this run kept\n"
    assert _tree(tmp_path) == before


def test_a_failed_replacement_leaves_the_old_run_intact(tmp_path, run_cli, monkeypatch):
    out = tmp_path / "o"
    assert run_cli(["reduced", "--json", "--out", str(out)])[0] == 0
    before = _tree(tmp_path)
    _interrupt_in_figures(monkeypatch, exc=lambda: OSError(28, "No space left on device"))
    code, _, err = run_cli(["reduced", "--replace", "--cycles", "2", "--out", str(out)])
    assert code == 1 and err == "error: No space left on device\n"
    assert _tree(tmp_path) == before


def test_replace_swaps_the_whole_folder(tmp_path, run_cli):
    """A run with figures replaced by one without: none of the old figures remain."""
    out = tmp_path / "o"
    assert run_cli(["reduced", "--json", "--out", str(out)])[0] == 0
    assert (out / "delta_vs_s.png").exists()
    code, _, err = run_cli(["reduced", "--json", "--no-figures", "--replace", "--out", str(out)])
    assert code == 0, err
    assert sorted(p.name for p in out.iterdir()) == [
        "config.json",
        "meta.json",
        "reduced.nc",
        "summary.json",
    ]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["o"]


def test_a_claimed_folder_refuses_a_simulate_before_its_solve(tmp_path, run_cli, monkeypatch):
    def never(*args, **kwargs):
        raise AssertionError("the solver ran although the folder was claimed")

    monkeypatch.setattr("bristlecrawler.jobs.simulate.solve", never)
    with claim_run_dir(tmp_path / "o", "test") as run:
        code, _, err = run_cli(["simulate", "paper", "--out", str(tmp_path / "o")])
        assert code == 2 and "being written by another run (pid" in err
        assert err.count("\n") == 1
        run.write_json("summary.json", {"x": float("nan")})
    assert _strict((tmp_path / "o" / "summary.json").read_text()) == {"x": None}


def test_a_folder_with_other_files_is_never_replaced(tmp_path):
    (tmp_path / "data").mkdir()
    (tmp_path / "data" / "notes.txt").write_text("mine")
    for replace in (False, True):
        with pytest.raises(InputError, match="holds no run"):
            claim_run_dir(tmp_path / "data", "test", replace=replace)
    assert (tmp_path / "data" / "notes.txt").read_text() == "mine"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["data"]


def test_an_empty_folder_takes_a_run(tmp_path):
    (tmp_path / "o").mkdir()
    with claim_run_dir(tmp_path / "o", "test") as run:
        run.write_json("summary.json", {})
    assert run_status(tmp_path / "o") == "complete"


def test_an_old_run_moved_aside_by_a_killed_replace_is_put_back(tmp_path):
    """Killed between the two renames of a replace: the old run is beside the target under
    a hidden name; the next claim restores it (and refuses, since it holds a run)."""
    old = tmp_path / ".o.old-abcd1234"
    old.mkdir()
    (old / "meta.json").write_text('{"status": "complete"}')
    with pytest.raises(InputError, match="already holds a run"):
        claim_run_dir(tmp_path / "o", "test")
    assert (tmp_path / "o" / "meta.json").exists() and not old.exists()


def test_an_exception_inside_the_claim_discards_everything(tmp_path):
    with pytest.raises(RuntimeError), claim_run_dir(tmp_path / "o", "test") as run:
        run.write_json("config.json", {})
        raise RuntimeError("solver blew up")
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("what", ["link to a file", "link to nothing", "fifo"])
def test_a_lock_file_planted_where_the_lock_goes_is_refused_and_not_written(
    tmp_path, run_cli, what
):
    """``reduced --out o`` with ``.o.lock`` a link or a FIFO: one line, exit 2, and the
    file the link points at keeps its content (nothing is created where it points)."""
    lock, victim = tmp_path / ".o.lock", tmp_path / "victim"
    if what == "link to a file":
        victim.write_text("precious\n")
        lock.symlink_to(victim)
    elif what == "link to nothing":
        lock.symlink_to(victim)
    else:
        os.mkfifo(lock)
    code, out, err = run_cli(["reduced", "--json", "--out", str(tmp_path / "o")])
    assert code == 2 and out == "" and err.count("\n") == 1
    assert ".o.lock" in err
    if what == "link to a file":
        assert victim.read_text() == "precious\n"
    else:
        assert not victim.exists()
    assert not (tmp_path / "o").exists()


@pytest.mark.parametrize("status", ["complete", "interrupted"])
def test_a_run_inside_another_run_s_folder_is_refused(tmp_path, run_cli, status):
    """A run folder is a unit: ``--out`` inside one (complete or not) is refused before
    any work, and the run it would have gone into is unchanged."""
    (tmp_path / "a").mkdir()
    (tmp_path / "a" / "meta.json").write_text(json.dumps({"status": status}))
    before = _tree(tmp_path)
    for inner in ("b", "b/c"):
        code, out, err = run_cli(["reduced", "--json", "--out", str(tmp_path / "a" / inner)])
        assert code == 2 and out == "" and err.count("\n") == 1
        assert "inside the run" in err
    assert _tree(tmp_path) == before


def test_a_run_may_hold_the_runs_it_writes_itself(tmp_path):
    """``reproduce`` writes its design studies inside its own folder while it runs; that
    is not a run inside another's. Once it is finished, a run inside it is refused."""
    with claim_run_dir(tmp_path / "outer", "outer") as outer:
        outer.write_metadata({}, "outer")
        with claim_run_dir(outer.path / "inner", "inner") as inner:
            inner.write_metadata({}, "inner")
    assert run_status(tmp_path / "outer" / "inner") == "complete"
    with pytest.raises(InputError, match="inside the run"):
        claim_run_dir(tmp_path / "outer" / "other", "other")


def test_a_fifo_as_a_run_s_meta_json_does_not_hang(tmp_path, run_cli):
    import threading

    (tmp_path / "o").mkdir()
    os.mkfifo(tmp_path / "o" / "meta.json")
    fired = []

    def unblock():  # a reader stuck on the FIFO goes on: the test fails, not hangs
        fired.append(True)
        os.close(os.open(tmp_path / "o" / "meta.json", os.O_WRONLY | os.O_NONBLOCK))

    timer = threading.Timer(10.0, unblock)
    timer.start()
    try:
        code, _, err = run_cli(["reduced", "--json", "--out", str(tmp_path / "o")])
    finally:
        timer.cancel()
    assert code == 2 and err.count("\n") == 1 and not fired
