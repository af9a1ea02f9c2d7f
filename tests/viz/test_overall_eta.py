"""``reproduce``'s overall bar and ETA, weighted by each part's expected time (its last run
here, or the reference machine's), compiling counted as work, the running part named.
A fake clock drives them: no test waits or times anything."""

import re
import textwrap

import pytest

from bristlecrawler.io.costs import record
from bristlecrawler.jobs.reproduce.parts import Settings
from bristlecrawler.jobs.reproduce.run import PARTS, _cost_key, _costs
from bristlecrawler.viz.parts_progress import Overall
from terminal import under_a_terminal


def test_a_part_that_reports_nothing_yet_is_done_by_its_time_so_far():
    """A compile reports no simulated time; its seconds still count, up to 95 % of the
    part's expected time."""
    t = [0.0]
    o = Overall({"small": 10.0, "big": 90.0}, clock=lambda: t[0])
    o.start("small")
    t[0] = 5.0
    assert o.done() == pytest.approx(5.0)
    assert o.eta() == pytest.approx(95.0)
    t[0] = 100.0  # far past its expected 10 s: never shown as done by time alone
    assert o.done() == pytest.approx(9.5)
    o.update(1.0)
    assert o.done() == pytest.approx(10.0)


def test_the_bar_is_weighted_by_the_expected_times_and_the_eta_by_the_runs_pace():
    t = [0.0]
    o = Overall({"small": 10.0, "big": 90.0}, clock=lambda: t[0])
    o.start("small")
    t[0] = 20.0  # twice as slow as expected
    o.finish("small", 20.0)
    o.start("big")
    assert o.done() == pytest.approx(10.0)  # a tenth of the work, not half the parts
    assert o.eta() == pytest.approx(180.0)  # the rest at this run's pace
    t[0] = 65.0
    o.update(0.5)
    assert o.done() == pytest.approx(55.0)
    assert o.eta() == pytest.approx(45.0 * (65.0 / 55.0))
    assert o.where() == "in big (2 of 2)"


SCRIPT = textwrap.dedent(
    """
    from bristlecrawler.viz.parts_progress import parts_progress

    t = [0.0]
    with parts_progress({"small": 10.0, "big": 90.0}, "whole", clock=lambda: t[0]) as bar:
        bar.start("small")
        t[0] = 10.0
        bar.finish("small", True, 10.0)
        bar.start("big")
        t[0] = 55.0
        bar.update(FRACTION)
    """
)


@pytest.mark.parametrize("fraction", [0.0, 0.5])
def test_on_a_terminal_the_whole_runs_bar_is_weighted_and_names_its_part(fraction):
    """Half of the big part's expected time gone, compiling (nothing reported) or half its
    simulated time done: 55 % of the whole, 45 s left, in the second part."""
    out = under_a_terminal(["python", "-c", SCRIPT.replace("FRACTION", repr(fraction))], 120)
    rows = [line for line in re.split(r"[\r\n]", out) if "whole" in line]
    assert rows, out[-2000:]
    last = re.sub(r"\x1b\[[0-9;?]*[A-Za-z]", "", rows[-1])
    assert " 55 %" in last, last
    assert "ETA 0:00:45" in last and "in big (2 of 2)" in last, last


def test_the_expected_times_are_each_parts_last_run_here_else_the_reference():
    settings = Settings.short()
    costs, line = _costs(PARTS, settings)
    assert costs == {p.name: p.reference_seconds(settings) for p in PARTS}
    assert line.startswith("not run here yet")
    record("reproduce", _cost_key(PARTS[1], settings), 400.0)
    costs, line = _costs(PARTS, settings)
    assert costs[PARTS[1].name] == 400.0
    assert costs[PARTS[2].name] == PARTS[2].reference_seconds(settings)
    assert f"1 of its {len(PARTS)} parts from their last runs here" in line
