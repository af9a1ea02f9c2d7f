"""Progress by default: bars on a terminal, one line per stage or part elsewhere, nothing
with ``--no-progress``; the stage notes (the compile announcement) in both forms."""

import io
import textwrap
from pathlib import Path

import pytest

from bristlecrawler.viz.parts_progress import parts_progress
from bristlecrawler.viz.progress import progress_mode, sim_progress
from terminal import under_a_terminal

ROOT = Path(__file__).resolve().parents[2]


class _Stream(io.StringIO):
    def __init__(self, tty: bool) -> None:
        super().__init__()
        self.tty = tty

    def isatty(self) -> bool:
        return self.tty


@pytest.mark.parametrize(
    ("enabled", "tty", "mode"),
    [
        (None, True, "bars"),
        (None, False, "lines"),
        (True, False, "bars"),
        (True, True, "bars"),
        (False, True, "off"),
        (False, False, "off"),
    ],
)
def test_the_default_is_bars_on_a_terminal_and_lines_elsewhere(enabled, tty, mode):
    assert progress_mode(enabled, _Stream(tty)) == mode


def test_a_stream_without_isatty_gets_lines():
    assert progress_mode(None, object()) == "lines"


def test_stage_notes_are_printed_when_the_stage_starts_and_timed_when_it_ends(capsys):
    notes = {"compiling": "compiling the FE programs for this structure, first time only"}
    with sim_progress(10.0, "crawler", enabled=None, notes=notes) as bar:
        bar.update(0.0, stage="compiling")
        bar.update(0.0, stage="compiling")
        bar.update(0.0, stage="gravity step")
        bar.update(5.0, stage="")
    lines = capsys.readouterr().err.splitlines()
    assert lines.count(notes["compiling"]) == 1
    done = [x for x in lines if x.startswith("compiling: done in ")]
    assert len(done) == 1 and lines.index(done[0]) > lines.index(notes["compiling"])


def test_no_progress_is_silent_even_for_notes(capsys):
    with parts_progress({"a": 1.0}, enabled=False) as bar:
        bar.start("a")
        bar.note("compiling ...")
        bar.finish("a", True, 1.0)
    with sim_progress(1.0, enabled=False, notes={"compiling": "x"}) as bar:
        bar.update(0.0, stage="compiling")
    assert capsys.readouterr().err == ""


def test_parts_lines_say_the_time_left_from_the_parts_expected_times(capsys):
    """The parts' expected times are seconds (their last runs here, or the reference
    machine's): the lines say what is left from the start, weighted by them."""
    t = [0.0]
    with parts_progress({"a": 10.0, "b": 90.0}, enabled=None, clock=lambda: t[0]) as bar:
        bar.start("a")
        t[0] = 10.0
        bar.finish("a", True, 10.0)
        bar.start("b")
        bar.note("compiling ...")
        bar.finish("b", True, 2.0)
    lines = capsys.readouterr().err.splitlines()
    assert "reproduce: a ... (0 s elapsed, about 100 s left)" in lines
    assert "reproduce: b ... (10 s elapsed, about 90 s left)" in lines
    assert "reproduce: compiling ..." in lines


SCRIPT = textwrap.dedent(
    """
    import time
    from bristlecrawler.viz.progress import sim_progress
    from bristlecrawler.viz.parts_progress import parts_progress

    notes = {"compiling": "NOTE compiling"}
    with sim_progress(10.0, "crawler", notes=notes) as bar:
        bar.update(0.0, stage="compiling")
        bar.update(5.0, stage="gravity step")
        time.sleep(0.2)
        bar.update(10.0)
    with parts_progress({"first": 1.0, "second": 1.0}) as bar:
        bar.start("first")
        bar.update(0.5)
        bar.finish("first", True, 0.1)
        bar.start("second")
        bar.finish("second", True, 0.1)
    """
)


def test_on_a_pseudo_terminal_the_default_draws_bars():
    """What a user sees in a terminal without options: rich's bars (the cursor moved to
    redraw them), the compile note as a line of its own, no log lines."""
    out = under_a_terminal(["python", "-c", SCRIPT])
    assert "\x1b[" in out, out[-2000:]  # terminal control: bars being redrawn
    assert "━" in out or "█" in out, out[-2000:]
    assert "NOTE compiling" in out
    assert "gravity step at t =" not in out  # the lines of a log are not printed
    assert "reproduce: first ..." not in out
    for name in ("crawler", "first", "second"):
        assert name in out


def test_a_stage_note_known_as_it_runs_says_what_the_stage_turned_out_to_be(capsys):
    from bristlecrawler.viz.progress import StageNote

    ended = []

    def end(seconds):
        ended.append(seconds)
        return "programs: loaded"

    notes = {"compiling": StageNote(lambda: "preparing programs", end)}
    with sim_progress(10.0, "crawler", enabled=None, notes=notes) as bar:
        bar.update(0.0, stage="compiling")
        bar.update(0.0, stage="gravity step")
    lines = capsys.readouterr().err.splitlines()
    assert lines.count("preparing programs") == 1 and lines.count("programs: loaded") == 1
    assert len(ended) == 1 and not any(x.startswith("compiling: done in") for x in lines)
