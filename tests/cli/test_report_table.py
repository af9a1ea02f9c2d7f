"""The report's table without running a solver: the verdict on "no advance" at alpha = 0,
each row's own reason, and the README's table, which shows a full run's table."""

import json
import math
import re
from pathlib import Path

import pytest
from hypothesis import assume, given
from hypothesis import strategies as st

from bristlecrawler.jobs.reproduce.parts import Context, PartResult, Settings
from bristlecrawler.jobs.reproduce.table import (
    BY_CONSTRUCTION,
    ROWS,
    SECTIONS,
    build_table,
    readme_table,
)
from bristlecrawler.jobs.reproduce.verdict import no_advance_verdict

ROOT = Path(__file__).resolve().parents[2]

finite = st.floats(-20.0, 20.0, allow_nan=False)


def test_the_reported_case_is_not_an_agreement():
    """-0.87 ± 3.18 mm from four places: the interval is far wider than ±2 mm."""
    v = no_advance_verdict([-7.99, 6.25, -4.0, 2.26], 2.0)
    assert v.mean == pytest.approx(-0.87)
    assert v.sem == pytest.approx(3.18, abs=0.01)
    assert v.verdict == "inconclusive"
    assert v.reason.startswith("consistent with no advance")
    assert f"{v.excluded:.2f}" in v.reason and v.excluded > 10


def test_a_tight_set_around_zero_agrees_and_a_steady_drift_differs():
    assert no_advance_verdict([0.1, -0.1, 0.05, -0.05, 0.0, 0.02], 2.0).verdict == "agrees"
    assert no_advance_verdict([16.0, 16.4, 16.2, 16.1], 2.0).verdict == "differs"


def test_one_place_gives_no_test():
    v = no_advance_verdict([0.3], 2.0)
    assert v.verdict == "inconclusive" and v.sem is None and "no standard error" in v.reason


@given(st.lists(finite, min_size=2, max_size=30), st.floats(0.1, 10.0))
def test_the_verdict_follows_the_interval(values, tol):
    v = no_advance_verdict(values, tol)
    assert v.low <= v.mean <= v.high
    assert v.excluded == pytest.approx(max(abs(v.low), abs(v.high)))
    if v.verdict == "agrees":
        assert -tol <= v.low and v.high <= tol
    elif v.verdict == "differs":
        assert v.low > tol or v.high < -tol
    else:
        assert v.low < -tol or v.high > tol
        assert not (v.low > tol or v.high < -tol)


@given(st.lists(finite, min_size=2, max_size=12), st.floats(0.1, 10.0))
def test_more_of_the_same_data_never_widens_the_interval(values, tol):
    """The same values twice over: a smaller standard error and t, never a weaker case."""
    assume(max(values) - min(values) > 1e-6)
    once, twice = no_advance_verdict(values, tol), no_advance_verdict(values * 2, tol)
    assert twice.high - twice.low <= once.high - once.low + 1e-12
    rank = {"inconclusive": 0, "agrees": 1, "differs": 1}
    assert rank[twice.verdict] >= rank[once.verdict]


@given(st.lists(finite, min_size=2, max_size=12), st.floats(0.1, 10.0))
def test_the_verdict_is_symmetric_under_a_mirror(values, tol):
    a, b = no_advance_verdict(values, tol), no_advance_verdict([-x for x in values], tol)
    assert a.verdict == b.verdict and a.excluded == pytest.approx(b.excluded)


def _ctx(vertical, source="synthetic"):
    ctx = Context(Settings.full(), Path("."))
    ctx.results["fe-paper"] = PartResult(
        "fe-paper",
        values={
            "net_advance_mm": 81.6,
            "advance_per_cycle_mm": [17.6, 16.0, 16.0, 16.0, 16.0],
            "work_mJ": 44.3,
            "mean_abs_connector_force_N": 0.21,
            "cycles": 5,
        },
    )
    cal = {"fp_over_k_mm": 0.94, "fp_N": 0.27, "k_N_per_mm": 0.29, "cycles": 5}
    ctx.results["reduced"] = PartResult("reduced", values={"fe_calibration": cal})
    ctx.results["experiment"] = PartResult(
        "experiment",
        values={"fp_over_k_mm": 0.956, "net_advance_mm": 81.8, "cycles": 5, "source": source},
    )
    mean = sum(vertical) / len(vertical)
    sem = math.sqrt(sum((x - mean) ** 2 for x in vertical) / (len(vertical) - 1) / len(vertical))
    ctx.results["fe-vertical"] = PartResult(
        "fe-vertical",
        values={
            "advance_per_cycle_mean_mm": mean,
            "advance_per_cycle_sem_mm": sem,
            "advance_per_cycle_mm": vertical,
            "starting_places_mm": [0.25 * i for i in range(len(vertical))],
        },
    )
    return ctx


def test_the_rows_verdicts_and_reasons():
    rows = {r.key: r for r in build_table(_ctx([-7.99, 6.25, -4.0, 2.26]))}
    alpha0 = rows["advance_alpha0_mm_per_cycle"]
    assert alpha0.verdict == "inconclusive" and alpha0.agrees is None
    assert "consistent with no advance" in alpha0.reason and alpha0.docs
    # F_p and k have their own reason, not the work row's words.
    assert rows["fp_N"].verdict == rows["k_N_per_mm"].verdict == "differs"
    assert rows["fp_N"].reason != rows["work_mJ"].reason
    assert "calibrated on our FE run" in rows["fp_N"].reason
    # The synthetic recording's rows agree by construction, and say so.
    for key in ("fp_over_k_recording_mm", "net_advance_recording_mm"):
        assert rows[key].verdict == "agrees" and rows[key].reason == BY_CONSTRUCTION
    for r in rows.values():
        assert r.verdict in ("agrees", "differs", "inconclusive", "n/a")
        if r.verdict in ("differs", "inconclusive"):
            assert r.docs == SECTIONS[r.link]


def test_a_given_recording_is_compared_plainly():
    rows = {r.key: r for r in build_table(_ctx([0.1, -0.1, 0.0], source="trial.csv"))}
    assert rows["fp_over_k_recording_mm"].reason.startswith("agrees within")
    assert rows["advance_alpha0_mm_per_cycle"].verdict == "agrees"


def test_every_documented_section_exists():
    for link, name in SECTIONS.items():
        page, _, anchor = link.partition("#")
        text = (ROOT / "docs" / page).read_text(encoding="utf-8")
        if anchor:
            heading = name.split("\u201c")[1].rstrip("\u201d")
            assert f"## {heading}" in text.replace("`", ""), name
    assert {spec.link for spec in ROWS} <= set(SECTIONS)


def _readme_section() -> str:
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    head = r"\| quantity \| paper \| bristlecrawler \| verdict \|"
    table = re.search(r"\n(" + head + r"\n(?:\|.*\n)+)", text)
    assert table, "the README has no results table"
    return table.group(1)


def test_the_readme_shows_the_reference_runs_table():
    """The README's table is the one a full run's table.json gives, row for row."""
    doc = json.loads((ROOT / "docs" / "results" / "table.json").read_text(encoding="utf-8"))
    assert _readme_section() == readme_table(doc)
    assert [r["key"] for r in doc["rows"]] == [spec.key for spec in ROWS]


def test_the_difference_column_is_signed_and_has_its_unit(tmp_path):
    """In both forms of the report: ``+0.400 mm`` for ours above the paper's,
    ``-2.500 mJ`` below it."""
    from bristlecrawler.jobs.reproduce.render import Report, markdown, to_html
    from bristlecrawler.jobs.reproduce.table import Row

    def row(key, unit, paper, ours):
        return Row(key, key, unit, paper, f"{paper}", ours, "", "test", True, "", "", "agrees")

    rows = (row("a_mm", "mm", 16.0, 16.4), row("w_mJ", "mJ", 30.0, 27.5))
    rep = Report("t", (), rows, ())
    for text in (markdown(rep), to_html(rep, tmp_path)):
        assert "+0.400 mm" in text and "-2.500 mJ" in text
        assert "ours - paper" in text
