"""The parts of ``bristlecrawler reproduce`` one at a time, the FE parts on the shared coarse
structure (``tests/structures.py``), then the table and the report built from them. The
end-to-end ``reproduce --quick`` run (one cycle of the paper's crawler, the drag test, the
design study) is ``test_reproduce_cli.py``'s, in the slow lane."""

import dataclasses
import re

import numpy as np
import pytest

from bristlecrawler.jobs.reproduce import fe_parts
from bristlecrawler.jobs.reproduce.experiment_part import EXPERIMENT, load_recording
from bristlecrawler.jobs.reproduce.fe_parts import FE_PAPER, FE_VERTICAL
from bristlecrawler.jobs.reproduce.parts import Context, Settings, run_part
from bristlecrawler.jobs.reproduce.reduced_part import REDUCED
from bristlecrawler.jobs.reproduce.table import build_table
from structures import COARSE, coarse_run

#: ``--quick``'s settings at the coarse structure's mesh, two starting places at alpha = 0
#: (so that the part gives a standard error).
SETTINGS = dataclasses.replace(Settings.short(), elements=4, vertical_phases=2)


def _coarse_scenario(name, ctx, sets):
    """The parts' scenario at the coarse structure, with the part's own values (cycles,
    the substrate's phase) after the coarse overrides. Each starting place is moved by
    half a land (0.5 mm): the part's places 0 and 1 mm become 0.5 and 1.5 mm, the lands
    or the grooves centred under both tips and under the body's middle, so that
    alpha = 0 is mirror symmetric (a coarse bristle's tip contact at a land edge is not
    what this checks)."""
    from bristlecrawler.scenario.load import apply_overrides, load_scenario

    def shifted(s):
        key, _, value = s.partition("=")
        return f"{key}={float(value) + 0.5!r}" if key == "substrate.phase" else s

    return apply_overrides(load_scenario(name), [*COARSE, *map(shifted, sets)])


@pytest.fixture(scope="module")
def ctx(tmp_path_factory):
    """A context after the experiment, both FE parts and the reduced part, in that order
    (the reduced part calibrates on the FE part's run)."""
    folder = tmp_path_factory.mktemp("reproduce-parts")
    ctx = Context(SETTINGS, folder, inputs={"recording": load_recording(None)})
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(fe_parts, "scenario", _coarse_scenario)
        for part in (EXPERIMENT, FE_PAPER, FE_VERTICAL, REDUCED):
            ctx.results[part.name] = run_part(part, ctx)
    return ctx


@pytest.mark.slow
def test_every_part_succeeds_and_writes_its_figures(ctx):
    for name, r in ctx.results.items():
        assert r.ok, (name, r.error)
        assert r.lines and r.wall_s > 0.0
        for fig in r.figures:
            assert (ctx.folder / fig.path).stat().st_size > 1000, fig.path
    assert any(f.path.endswith(".gif") for f in ctx.results["fe-paper"].figures)


@pytest.mark.slow
def test_the_fe_part_reports_its_runs_own_numbers(ctx):
    """The part's numbers are those of the same scenario run directly: its advance per
    cycle sums to its net advance, and its work is the connector's."""
    v = ctx.results["fe-paper"].values
    assert v["cycles"] == 1 and v["elements"] == 4
    _, h = coarse_run("paper")
    assert v["net_advance_mm"] == pytest.approx(h.net_advance, abs=1e-9)
    assert sum(v["advance_per_cycle_mm"]) == pytest.approx(v["net_advance_mm"], abs=1e-9)
    assert v["work_mJ"] == pytest.approx(h.connector_work[-1], rel=1e-9) and v["work_mJ"] > 0.0
    assert v["steps"] == h.stats["steps"]


def test_the_vertical_part_runs_each_starting_place_and_takes_their_mean(ctx):
    """Two starting places half a pitch apart, each one cycle; the mean and its standard
    error are those of the cycles."""
    v = ctx.results["fe-vertical"].values
    assert v["starting_places_mm"] == pytest.approx([0.0, 1.0])  # half the 2 mm pitch
    adv = np.asarray(v["advance_per_cycle_mm"])
    assert v["failed_starting_places"] == 0 and adv.size == 2
    # Both places are mirror symmetric about the body's middle: no advance.
    assert np.all(np.abs(adv) < 1e-6)
    assert v["advance_per_cycle_mean_mm"] == pytest.approx(adv.mean(), abs=1e-12)
    assert v["advance_per_cycle_sem_mm"] == pytest.approx(adv.std(ddof=1) / np.sqrt(2), abs=1e-12)


def test_the_reduced_part_gives_back_the_papers_numbers_and_calibrates_on_the_fe_run(ctx):
    """Calibrated on the paper's 82 mm and 75 mJ, the reduced model gives them back (by
    construction); calibrated on our FE run, it says which run (one cycle) or why not."""
    v = ctx.results["reduced"].values
    assert v["net_advance_mm"] == pytest.approx(82.0, abs=0.1)
    assert v["work_mJ"] == pytest.approx(75.0, rel=0.01)
    assert v["paper_calibration"]["fp_over_k_mm"] == pytest.approx(0.95, abs=0.01)
    ours = v["fe_calibration"]
    assert "error" in ours or (ours["cycles"] == 1 and ours["fp_over_k_mm"] > 0.0)


def test_the_table_takes_each_row_from_its_part(ctx):
    rows = {r.key: r for r in build_table(ctx)}
    fe = ctx.results["fe-paper"].values
    # Five-cycle quantities are not compared on one cycle; the per-cycle advance is.
    assert rows["net_advance_mm"].ours is None and "1 cycle" in rows["net_advance_mm"].ours_text
    assert rows["advance_per_cycle_mm"].ours == pytest.approx(fe["net_advance_mm"], abs=1e-12)
    assert rows["advance_alpha0_mm_per_cycle"].ours == pytest.approx(
        ctx.results["fe-vertical"].values["advance_per_cycle_mean_mm"], abs=1e-12
    )
    # The synthetic recording gives back the F_p/k it was made with.
    assert rows["fp_over_k_recording_mm"].ours == pytest.approx(0.456 / 0.48, abs=0.02)
    # The drag part did not run: its rows say so instead of a number.
    assert rows["fp_drag_N"].ours is None and "drag not run" in rows["fp_drag_N"].ours_text


def test_the_report_of_these_parts_links_only_files_it_wrote(ctx):
    from bristlecrawler.jobs.reproduce.render import Report, markdown, to_html
    from bristlecrawler.jobs.reproduce.run import TITLE

    parts = tuple((p, ctx.results[p.name]) for p in (EXPERIMENT, FE_PAPER, FE_VERTICAL, REDUCED))
    report = Report(TITLE, ("header",), tuple(build_table(ctx)), parts)
    text = markdown(report)
    links = [x for x in re.findall(r"\]\(([^)\s]+)\)", text) if not x.startswith("http")]
    assert links and all((ctx.folder / x.partition("#")[0]).exists() for x in links)
    page = to_html(report, ctx.folder)
    assert len(re.findall(r'<img src="data:', page)) >= 6 and "This part failed" not in page
