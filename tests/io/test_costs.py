"""The measured costs behind the estimates long commands print before they start."""

import dataclasses
import os
import stat

import pytest

from bristlecrawler.io import costs
from bristlecrawler.jobs import estimates


def test_a_recorded_cost_is_read_back_and_replaced():
    assert costs.recorded("simulate", "k") is None
    costs.record("simulate", "k", 12.5)
    assert costs.recorded("simulate", "k").seconds == 12.5
    costs.record("simulate", "k", 30.0)
    assert costs.recorded("simulate", "k").seconds == 30.0
    assert costs.recorded("simulate", "other") is None


@pytest.mark.parametrize("bad", [float("nan"), float("inf"), -1.0])
def test_a_cost_that_is_not_a_duration_is_not_kept(bad):
    costs.record("compile", "k", bad)
    assert costs.recorded("compile", "k") is None


def test_a_file_the_tool_did_not_write_gives_no_estimate_and_is_left_as_it_is():
    costs.costs_path().parent.mkdir(parents=True, exist_ok=True)
    costs.costs_path().write_text("{not json")
    assert costs.recorded("simulate", "k") is None
    costs.record("simulate", "k", 3.0)
    assert costs.costs_path().read_text() == "{not json"


def _unfit_costs(tmp_path, what):
    """A path ``BRISTLECRAWLER_COSTS`` may name that the costs must not be written to."""
    path = tmp_path / "notes.txt"
    if what == "notes":
        path.write_text("my notes\n")
    elif what == "link":
        (tmp_path / "costs.json").write_text('{"simulate": {"k": {"seconds": 1}}}')
        path.symlink_to(tmp_path / "costs.json")
    elif what == "fifo":
        os.mkfifo(path)
    elif what == "folder":
        path.mkdir()
    elif what == "device":
        # A device of the test's own (the code before this check replaced what the
        # variable named: never point it at the real /dev/null).
        try:
            os.mknod(path, stat.S_IFCHR | 0o666, os.makedev(1, 3))
        except (PermissionError, AttributeError):
            pytest.skip("making a device needs root")
    return path


@pytest.mark.parametrize("what", ["notes", "link", "fifo", "folder", "device"])
def test_bristlecrawler_costs_naming_what_the_tool_did_not_make_is_refused(
    tmp_path, monkeypatch, run_cli, what
):
    path = _unfit_costs(tmp_path, what)
    before = os.lstat(path)
    content = path.read_text() if what == "notes" else None
    monkeypatch.setenv("BRISTLECRAWLER_COSTS", str(path))
    code, out, err = run_cli(["reduced", "--cycles", "1", "--out", str(tmp_path / "run")])
    assert (code, out, err.count("\n")) == (2, "", 1), err
    assert err.startswith("error: BRISTLECRAWLER_COSTS=") and "BRISTLECRAWLER_NO_COSTS=1" in err
    assert not (tmp_path / "run").exists()
    # The library writes nothing there either: what was there stays as it was.
    costs.record("simulate", "k", 3.0)
    after = os.lstat(path)
    assert (after.st_ino, after.st_mode, after.st_size) == (
        before.st_ino,
        before.st_mode,
        before.st_size,
    )
    if content is not None:
        assert path.read_text() == content


def test_the_costs_file_is_replaced_atomically_and_is_the_user_s_alone(tmp_path, monkeypatch):
    path = tmp_path / "costs.json"
    monkeypatch.setenv("BRISTLECRAWLER_COSTS", str(path))
    costs.record("simulate", "k", 3.0)
    first = os.stat(path).st_ino
    costs.record("simulate", "j", 4.0)
    assert os.stat(path).st_ino != first  # a new file renamed over the old one
    assert stat.S_IMODE(os.stat(path).st_mode) == 0o600
    assert [costs.recorded("simulate", k).seconds for k in "kj"] == [3.0, 4.0]
    assert list(tmp_path.iterdir()) == [path]


def test_bristlecrawler_no_costs_keeps_none_and_reads_none(tmp_path, monkeypatch, run_cli):
    notes = tmp_path / "notes.txt"
    notes.write_text("my notes\n")
    monkeypatch.setenv("BRISTLECRAWLER_COSTS", str(notes))
    monkeypatch.setenv("BRISTLECRAWLER_NO_COSTS", "1")
    costs.record("simulate", "k", 3.0)
    assert costs.recorded("simulate", "k") is None
    code, _, _ = run_cli(["reduced", "--cycles", "1", "--out", str(tmp_path / "run")])
    assert code == 0 and notes.read_text() == "my notes\n"


@pytest.mark.parametrize("value", ["", "relative/cache"])
def test_an_empty_or_relative_xdg_cache_home_is_ignored(tmp_path, monkeypatch, value):
    from bristlecrawler.fe.cache import cache_folder
    from bristlecrawler.jobs.predict import cache_folder as drag_cache

    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("HOME", str(tmp_path / "home"))
    monkeypatch.setenv("XDG_CACHE_HOME", value)
    monkeypatch.setenv("XDG_CONFIG_HOME", value)
    for name in ("BRISTLECRAWLER_COSTS", "BRISTLECRAWLER_JAX_CACHE", "BRISTLECRAWLER_CACHE_KEY"):
        monkeypatch.delenv(name, raising=False)
    monkeypatch.delenv("BRISTLECRAWLER_NO_JAX_CACHE", raising=False)
    monkeypatch.delenv("BRISTLECRAWLER_DRAG_CACHE", raising=False)
    from bristlecrawler.fe.program_store import key_path

    home = tmp_path / "home"
    assert costs.costs_path() == home / ".cache" / "bristlecrawler" / "costs.json"
    assert cache_folder() == home / ".cache" / "bristlecrawler" / "jax"
    assert drag_cache() == home / ".cache" / "bristlecrawler" / "drag"
    assert key_path() == home / ".config" / "bristlecrawler" / "cache-key"
    costs.record("simulate", "k", 3.0)
    assert costs.recorded("simulate", "k").seconds == 3.0
    assert [p.name for p in tmp_path.iterdir()] == ["home"]  # nothing in the current folder


@pytest.mark.parametrize(
    ("seconds", "text"),
    [(0.2, "about 1 s"), (45, "about 45 s"), (600, "about 10 min"), (9000, "about 2.5 h")],
)
def test_durations_read_as_a_person_says_them(seconds, text):
    assert costs.duration(seconds) == text


def test_the_compile_line_promises_neither_a_load_nor_a_compile(monkeypatch):
    """Whether a design's programs are in the cache is known only once they are prepared
    (its values can change the arrays they are built for): the line before says what
    either costs, from this machine's measurements where there are some."""
    from bristlecrawler.crawler import CrawlerSpec

    monkeypatch.delenv("BRISTLECRAWLER_NO_JAX_CACHE", raising=False)
    spec = CrawlerSpec.paper()
    first = estimates.compile_note(spec)
    assert first.startswith("preparing the crawler's FE programs") and "else compiled" in first
    assert "about 70 s for the paper's crawler" in first
    estimates.record_compile(spec, 75.0)
    again = estimates.compile_note(spec)
    assert not again.startswith("loading") and "compiling took about 75 s here" in again
    # The drag rig's programs are other programs: the crawler's figure is not theirs.
    drag = estimates.compile_note(spec, "drag")
    assert "drag rig" in drag and "paper's crawler" not in drag and "75 s" not in drag
    assert "no compile of them measured here yet" in drag
    # The drag rig's programs do not hold the crawler's stroke: a sampled one shares them.
    estimates.record_compile(spec, 40.0, "drag")
    history = ((0.0, 1.0, 2.0), (0.0, 1.0, 0.0))
    sampled = dataclasses.replace(
        spec, actuation=dataclasses.replace(spec.actuation, history=history)
    )
    assert "about 40 s here" in estimates.compile_note(sampled, "drag")
    assert "about 70 s for the paper's crawler" in estimates.compile_note(sampled)
    # Another version of the package (or other XLA flags) stores other programs.
    from bristlecrawler.fe import programs

    monkeypatch.setattr(programs, "environment", lambda: "another version")
    assert "about 70 s for the paper's crawler" in estimates.compile_note(spec)
    monkeypatch.setenv("BRISTLECRAWLER_NO_JAX_CACHE", "1")
    assert "every run compiles" in estimates.compile_note(spec)


@pytest.mark.parametrize(
    ("compiled", "loaded", "says", "kept"),
    [
        (2, 0, "the crawler's FE programs: compiled in 92 s", True),
        (0, 5, "the crawler's FE programs: loaded from the compilation cache in 92 s", False),
        (1, 4, "1 compiled and 4 loaded from the compilation cache in 92 s", True),
        (0, 0, "ready in 92 s (this process had them already)", False),
    ],
)
def test_the_line_after_says_what_the_preparation_was(monkeypatch, compiled, loaded, says, kept):
    """Loading is said only where nothing compiled; only a compile's time is kept for the
    next estimate (a load's seconds would make a false one)."""
    from bristlecrawler.crawler import CrawlerSpec
    from bristlecrawler.fe import programs

    monkeypatch.delenv("BRISTLECRAWLER_NO_JAX_CACHE", raising=False)
    spec = CrawlerSpec.paper()
    start = programs.counts()
    prep = estimates.Preparation(spec)
    after = {"compiled": start["compiled"] + compiled, "loaded": start["loaded"] + loaded}
    monkeypatch.setattr(programs, "counts", lambda: dict(after))
    assert says in prep.outcome(92.0)
    assert ("loaded" in prep.outcome(92.0)) == (loaded > 0)
    prep.finish({"compile_time_s": 92.0})
    kept_cost = costs.recorded("compile", estimates.compile_key(spec))
    assert (kept_cost is not None) == kept


def test_an_estimate_names_its_source():
    key = estimates.scenario_key("simulate", {"name": "a", "output": {"vtk": True}, "x": 1})
    same = estimates.scenario_key("simulate", {"name": "b", "output": {"vtk": False}, "x": 1})
    assert key == same  # the outputs and the name do not change the run
    assert estimates.expected("simulate", key, "no earlier run") == "no earlier run"
    costs.record("simulate", key, 130.0)
    text = estimates.expected("simulate", key, "no earlier run")
    assert text.startswith("expected about 2 min once the FE programs are ready")
    assert estimates.run_seconds(700.0, {"compile_time_s": 600.0}) == 100.0
    assert estimates.run_seconds(700.0, {}) == 700.0
