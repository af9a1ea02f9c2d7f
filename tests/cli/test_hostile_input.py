"""Input a hostile user would give: names that would leave the runs folder, work larger
than the machine, a scheduler that never answers, cells and columns that are not there."""

import socket
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from bristlecrawler.errors import InputError
from bristlecrawler.io.output_paths import SAFE_NAME, check_safe_name, folder_in, safe_stem
from bristlecrawler.scenario.cost import Estimate, machine_memory


@settings(max_examples=300, deadline=None)
@given(name=st.text(max_size=80))
def test_a_name_is_refused_or_names_a_folder_inside_runs(tmp_path_factory, name):
    root = tmp_path_factory.mktemp("root") / "runs"
    try:
        check_safe_name(name)
    except ValueError as exc:
        assert "a name must be" in str(exc)
        assert not SAFE_NAME.fullmatch(name)
        return
    path = folder_in(root, f"20260101-000000-simulate-{name}")
    assert path.parent == root and not root.exists()


@pytest.mark.parametrize("name", ["..", "../x", "a/../..", "/etc", "x/y"])
def test_a_folder_name_that_leaves_its_root_is_refused_before_anything_exists(tmp_path, name):
    with pytest.raises(InputError, match="would leave"):
        folder_in(tmp_path / "runs", name)
    assert list(tmp_path.iterdir()) == []


@given(stem=st.text(max_size=100))
def test_a_scenario_file_without_a_name_gets_a_safe_one_from_its_stem(stem):
    assert check_safe_name(safe_stem(stem))


@given(memory=st.floats(0, 1e15), steps=st.floats(0, 1e8))
def test_an_estimate_is_refused_exactly_beyond_the_machine_with_the_estimate(memory, steps):
    est = Estimate("the work", steps, "time steps", 10.0, memory)
    fits = memory <= 0.8 * machine_memory() and steps <= 1e6
    try:
        est.check()
    except InputError as exc:
        assert not fits and str(exc).startswith(est.text())
        return
    assert fits


@given(
    n=st.integers(0, 10_000),
    chunk=st.integers(1, 300),
    finished=st.sets(st.integers(-3, 200), max_size=20),
)
def test_the_tasks_left_are_counted_without_making_them(n, chunk, finished):
    from bristlecrawler.studies.runner import task_count, tasks_of

    values = np.arange(n, dtype=float)
    designs = SimpleNamespace(n=n, keys=("s_max",), values={"s_max": values})
    plan = SimpleNamespace(
        study=SimpleNamespace(tasks_chunk=chunk, reduced_solver="auto"),
        designs=designs,
        base=SimpleNamespace(model="reduced", config={}),
    )
    tasks = list(tasks_of(plan, finished))
    assert task_count(plan, finished) == (len(tasks), sum(t.index.size for t in tasks))
    assert sorted(int(i) for t in tasks for i in t.index) == sorted(
        i for i in range(n) if i // chunk not in finished
    )


def test_a_scheduler_that_never_answers_is_refused_after_the_timeout(tmp_path):
    import time

    from bristlecrawler.studies.execute import connect

    with socket.socket() as s:  # listens, never replies
        s.bind(("127.0.0.1", 0))
        s.listen(4)
        address = f"tcp://127.0.0.1:{s.getsockname()[1]}"
        t0 = time.perf_counter()
        with pytest.raises(InputError, match="cannot reach the Dask scheduler"):
            connect(address, None, timeout_s=1.0)
        assert time.perf_counter() - t0 < 30  # refused, not the 95 s of a handshake wait


@pytest.mark.parametrize("address", ["", "notanaddress", "http://127.0.0.1:1", "tcp://h:0"])
def test_a_scheduler_address_is_checked_on_sight(tmp_path, run_cli, address):
    study = tmp_path / "s.toml"
    study.write_text('name = "s"\nmodel = "reduced"\n[axes]\ns_max = [10.0]\n')
    out = tmp_path / "o"
    code, _, err = run_cli(["sweep", str(study), "--scheduler", address, "--out", str(out)])
    assert (code, err.count("\n")) == (2, 1) and "is not a Dask scheduler address" in err
    assert not out.exists()


def test_cells_that_are_not_numbers_are_counted_and_reported(tmp_path):
    import warnings

    from bristlecrawler.experiment.readers import read_csv

    rows = ["time_s,left_mm,right_mm"] + [f"{i / 100},{i / 10},{i / 10 + 1}" for i in range(50)]
    rows[5], rows[9] = "0.04,abc,1.4", "0.08,0.8,x"
    rows[12] = "0.11,,nan"  # empty and nan are dropouts, said nothing about
    (tmp_path / "r.csv").write_text("\n".join(rows) + "\n")
    with warnings.catch_warnings(record=True) as seen:
        warnings.simplefilter("always")
        rec = read_csv(tmp_path / "r.csv")
    assert [str(w.message).split(": ", 1)[1] for w in seen] == [
        "2 cells that are not numbers (first: data row 5, column 2) read as dropouts"
    ]
    assert np.isnan(rec.left[[4, 11]]).all() and np.isnan(rec.right[[8, 11]]).all()


def test_a_large_recording_is_read_in_chunks_like_a_small_one(tmp_path, monkeypatch):
    from bristlecrawler.experiment import readers

    t = np.arange(1000) / 100
    text = "time_s,left_mm,right_mm\n" + "".join(f"{a},{a * 2},{a * 3}\n" for a in t)
    (tmp_path / "r.csv").write_text(text)
    whole = readers.read_csv(tmp_path / "r.csv")
    monkeypatch.setattr(readers, "CHUNK_ROWS", 7)
    chunked = readers.read_csv(tmp_path / "r.csv")
    assert np.array_equal(whole.t, chunked.t) and np.array_equal(whole.right, chunked.right)


@pytest.mark.parametrize(
    ("args", "words"),
    [
        (["--time", "nosuch"], "no time column 'nosuch'"),
        (["--force", "nosuch"], "no force column 'nosuch'"),
        (["--left", "nosuch"], "no left-end channel 'nosuch'"),
    ],
)
def test_a_named_column_that_is_not_there_is_an_error(tmp_path, run_cli, args, words):
    rows = "time_s,left_mm,right_mm\n" + "".join(f"{i},{i},{i}\n" for i in range(20))
    (tmp_path / "r.csv").write_text(rows)
    out = tmp_path / "o"
    code, _, err = run_cli(["analyze", str(tmp_path / "r.csv"), *args, "--out", str(out)])
    assert (code, err.count("\n")) == (2, 1) and words in err
    assert not out.exists()


@pytest.mark.parametrize(
    ("sets", "words"),
    [
        (["actuation.history='h.csv'"], "actuation.history is set but actuation.kind is 'sin2'"),
        (["bristle.thickness_tip=3.5"], "must not exceed bristle.thickness_clamp"),
        (["name='../../escape'"], "a name must be"),
    ],
)
@pytest.mark.parametrize("command", ["simulate", "drag"])
def test_a_key_without_effect_a_reversed_taper_and_an_unsafe_name_are_refused(
    tmp_path, run_cli, monkeypatch, command, sets, words
):
    monkeypatch.chdir(tmp_path)
    args = [command, "paper", *[x for s in sets for x in ("--set", s)]]
    code, _, err = run_cli(args)
    assert (code, err.count("\n")) == (2, 1) and words in err, err
    assert list(Path(tmp_path).iterdir()) == []
