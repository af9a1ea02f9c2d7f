"""The measured costs behind the estimates long commands print before they start."""

import dataclasses

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


def test_an_unreadable_file_gives_no_estimate_and_no_error():
    costs.costs_path().parent.mkdir(parents=True, exist_ok=True)
    costs.costs_path().write_text("{not json")
    assert costs.recorded("simulate", "k") is None
    costs.record("simulate", "k", 3.0)  # and is replaced by a valid one
    assert costs.recorded("simulate", "k").seconds == 3.0


@pytest.mark.parametrize(
    ("seconds", "text"),
    [(0.2, "about 1 s"), (45, "about 45 s"), (600, "about 10 min"), (9000, "about 2.5 h")],
)
def test_durations_read_as_a_person_says_them(seconds, text):
    assert costs.duration(seconds) == text


def test_the_compile_line_says_first_time_then_loading(monkeypatch):
    from bristlecrawler.crawler import CrawlerSpec

    monkeypatch.delenv("BRISTLECRAWLER_NO_JAX_CACHE", raising=False)
    spec = CrawlerSpec.paper()
    first = estimates.compile_note(spec)
    assert first.startswith("compiling the FE programs for this structure, first time only")
    estimates.record_compile(spec, 75.0)
    again = estimates.compile_note(spec)
    assert again.startswith("loading the FE programs") and "about 75 s" in again
    # A drag test builds other programs: its first time is still a first time.
    assert "first time only" in estimates.compile_note(spec, "drag")
    # The drag rig's programs do not hold the crawler's stroke: a sampled one loads them.
    estimates.record_compile(spec, 40.0, "drag")
    history = ((0.0, 1.0, 2.0), (0.0, 1.0, 0.0))
    sampled = dataclasses.replace(
        spec, actuation=dataclasses.replace(spec.actuation, history=history)
    )
    assert estimates.compile_note(sampled, "drag").startswith("loading the FE programs")
    assert "first time only" in estimates.compile_note(sampled)
    # Another version of the package (or other XLA flags) stores other programs.
    from bristlecrawler.fe import programs

    monkeypatch.setattr(programs, "environment", lambda: "another version")
    assert "first time only" in estimates.compile_note(spec)
    monkeypatch.setenv("BRISTLECRAWLER_NO_JAX_CACHE", "1")
    assert "every run compiles" in estimates.compile_note(spec)


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
