"""``bristlecrawler reproduce``: the paper's analysis steps in order, then the report.

1. Check the input at the edge: the output folder, the recording (read and analysed), so
   that bad input ends with one line and nothing written.
2. Claim the run folder (:func:`bristlecrawler.io.runs.claim_run_dir`) and write the
   resolved settings and provenance.
3. Run the parts in order (experiments, FE at pi/4, FE at 0, reduced model and its
   calibration, drag test, design study); a part that fails is reported in its section.
4. Fill the table "paper versus bristlecrawler", write ``report.md``, ``report.html``,
   ``table.json``.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from bristlecrawler.jobs.reproduce.drag_part import DRAG
from bristlecrawler.jobs.reproduce.experiment_part import EXPERIMENT, load_recording
from bristlecrawler.jobs.reproduce.fe_parts import FE_PAPER, FE_VERTICAL
from bristlecrawler.jobs.reproduce.parts import Context, Part, PartResult, Settings, run_part
from bristlecrawler.jobs.reproduce.reduced_part import REDUCED
from bristlecrawler.jobs.reproduce.render import Report, markdown, to_html
from bristlecrawler.jobs.reproduce.study_part import STUDY
from bristlecrawler.jobs.reproduce.table import Row, build_table
from bristlecrawler.viz.progress import announce

#: The report's sections, in the order they run (later parts read earlier results).
PARTS: tuple[Part, ...] = (EXPERIMENT, FE_PAPER, FE_VERTICAL, REDUCED, DRAG, STUDY)

TITLE = "Noselli & DeSimone's bristle crawler, reproduced with bristlecrawler"


@dataclass(frozen=True)
class ReproduceOptions:
    """out: the run folder [default runs/<stamp>-reproduce]; quick: the short version;
    recording: a CSV/TDMS recording to analyse instead of the synthetic one; progress:
    bars on stderr [default: on a terminal]; command: for meta.json; parts: the sections."""

    out: Path | None = None
    quick: bool = False
    recording: Path | None = None
    progress: bool | None = None
    command: str = ""
    parts: tuple[Part, ...] = PARTS


@dataclass(frozen=True)
class ReproduceRun:
    """A finished report: the table, each part's result and where it was written."""

    rows: tuple[Row, ...]
    results: dict[str, PartResult]
    out_dir: Path
    notes: tuple[str, ...] = ()

    @property
    def failed(self) -> tuple[str, ...]:
        return tuple(n for n, r in self.results.items() if not r.ok)

    def table_json(self) -> dict[str, Any]:
        """The table and each part's status, as ``--json`` prints it."""
        return {
            "rows": [r.as_dict() for r in self.rows],
            "parts": {
                n: {"ok": r.ok, "error": r.error or None, "wall_s": r.wall_s, "values": r.values}
                for n, r in self.results.items()
            },
            "failed": list(self.failed),
            "report_html": str(self.out_dir / "report.html"),
            "output_dir": str(self.out_dir),
        }


def run_reproduce(opts: ReproduceOptions) -> ReproduceRun:
    """Run every part and write the report (see the module)."""
    from bristlecrawler.fe import enable_compilation_cache
    from bristlecrawler.io.runs import check_out_dir, claim_run_dir

    settings = Settings.short() if opts.quick else Settings.full()
    check_out_dir(opts.out)
    recording = load_recording(opts.recording)
    enable_compilation_cache()
    with claim_run_dir(opts.out, "reproduce", command=opts.command) as run:
        config = {
            "settings": dataclasses.asdict(settings),
            "recording": None if opts.recording is None else str(opts.recording),
            "parts": [p.name for p in opts.parts],
        }
        info = run.write_metadata(config, opts.command)
        costs, expect = _costs(opts.parts, settings)
        if opts.progress is not False:
            announce("reproduce", f"results go to {run.target}; {expect}")
        ctx = Context(settings, run.path, inputs={"recording": recording})
        _run_parts(opts, ctx, costs)
        rows = tuple(build_table(ctx))
        header = _header(info, settings, ctx)
        report = Report(TITLE, header, rows, tuple((p, ctx.results[p.name]) for p in opts.parts))
        out = ReproduceRun(rows, dict(ctx.results), run.target, tuple(run.notes))
        _write(run, report, out)
    return out


#: Measured times, until the parts ran on this machine (the reproduce guide's table).
FULL_REFERENCE = (
    "a full run took 11 min on an idle 2-core machine with an empty compilation cache, "
    "over an hour on a busy one"
)
QUICK_REFERENCE = (
    "--quick took 3 min on an idle 2-core machine with an empty compilation cache, "
    "21 min on a busy one"
)


def _cost_key(part: Part, settings: Settings) -> str:
    return f"{part.name}-{'quick' if settings.quick else 'full'}"


def _costs(parts: tuple[Part, ...], settings: Settings) -> tuple[dict[str, float], str]:
    """Each part's expected time, s (its last run here, else its time on the reference
    machine), and the line that says how long the run should take."""
    from bristlecrawler.io.costs import duration, recorded

    measured = {p.name: recorded("reproduce", _cost_key(p, settings)) for p in parts}
    seconds = {
        p.name: max(m.seconds, 0.01) if m is not None else p.reference_seconds(settings)
        for p, m in zip(parts, measured.values(), strict=True)
    }
    total = duration(sum(seconds.values()))
    here = [m for m in measured.values() if m is not None]
    if len(here) == len(parts):
        when = max(m.utc for m in here)[:10]
        return seconds, f"expected {total} (its parts' last runs here, {when})"
    if here:
        return seconds, (
            f"expected {total} ({len(here)} of its {len(parts)} parts from their last runs "
            "here, the others from the reference machine's times)"
        )
    reference = QUICK_REFERENCE if settings.quick else FULL_REFERENCE
    return seconds, f"not run here yet; {reference}"


def _run_parts(opts: ReproduceOptions, ctx: Context, costs: dict[str, float]) -> None:
    from bristlecrawler.io.costs import record
    from bristlecrawler.viz.parts_progress import parts_progress

    with parts_progress(costs, enabled=opts.progress) as bar:
        for part in opts.parts:
            bar.start(part.name)
            ctx.progress, ctx.note = bar.update, bar.note
            result = run_part(part, ctx)
            ctx.results[part.name] = result
            bar.finish(part.name, result.ok, result.wall_s)
            if result.ok:
                record("reproduce", _cost_key(part, ctx.settings), result.wall_s)


def _header(info, settings: Settings, ctx: Context) -> tuple[str, ...]:
    mode = (
        "`--quick` (fewer cycles, fewer starting places, shorter drag legs)"
        if settings.quick
        else "full"
    )
    wall = sum(r.wall_s for r in ctx.results.values())
    failed = [n for n, r in ctx.results.items() if not r.ok]
    lines = [
        "N. Noselli and A. DeSimone, *A robotic crawler exploiting directional frictional "
        "interactions: experiments, numerics, and derivation of a reduced model*: each of "
        "its results computed again by the toolkit, beside the paper's.",
        "",
        f"* bristlecrawler {info.version}, git revision `{info.git_revision}`, "
        f"run `{info.run_id}` (started {info.started})",
        f"* version: {mode}; {settings.elements} elements per bristle, "
        f"{settings.fe_cycles} FE cycle(s) at alpha = pi/4, {settings.vertical_phases} "
        f"starting place{'s' * (settings.vertical_phases > 1)} at alpha = 0; "
        f"computed in {wall:.0f} s{f' ({wall / 60:.0f} min)' if wall >= 90 else ''} on "
        f"{_machine()}",
        f"* parts that failed: {', '.join(failed) if failed else 'none'}",
        "* verdicts: *agrees* within the row's tolerance, *differs* beyond it, *inconclusive* "
        "where the data cannot tell (alpha = 0: a 95 % interval of the mean wider than the "
        "tolerance), *n/a* not compared",
    ]
    return tuple(lines)


def _machine() -> str:
    """The machine the run's time was measured on, as the report states it."""
    import os
    import platform

    return f"{os.cpu_count()} cores ({platform.machine()}, {platform.system()})"


def _write(run, report: Report, out: ReproduceRun) -> None:
    from bristlecrawler.io.atomic import atomic_write_text

    atomic_write_text(run.path / "report.md", markdown(report))
    atomic_write_text(run.path / "report.html", to_html(report, run.path))
    run.write_json("table.json", out.table_json())
    run.results_written("report.html")
