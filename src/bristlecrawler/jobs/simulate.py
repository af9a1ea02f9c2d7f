"""The ``bristlecrawler simulate`` job: run an FE crawler scenario and write its results.

Output folder (``runs/<timestamp>-simulate-<name>`` unless given): ``config.json`` (the
resolved scenario), ``scenario.toml`` (the same as a scenario file: ``bristlecrawler
simulate runs/<id>/scenario.toml`` runs it again), ``meta.json`` (package version, git
revision, command), ``crawler.nc`` (time series and frames, xarray/NetCDF),
``vtk/crawler.pvd`` (ParaView series), ``delta_vs_s.png``, ``shapes.png``,
``connector.png``, ``crawler.gif`` (and ``crawler.mp4`` with the ``video`` extra) and
``summary.json``. Every file is written atomically, and only after the solve succeeded.
"""

from __future__ import annotations

import dataclasses
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from bristlecrawler.crawler.history import CrawlerHistory
from bristlecrawler.errors import printable
from bristlecrawler.scenario.schema import Scenario


@dataclass(frozen=True)
class SimulationRun:
    """A finished FE crawler run: its history, summary and output folder."""

    history: CrawlerHistory
    summary: dict[str, Any]
    out_dir: Path | None
    notes: tuple[str, ...] = ()


def summary_json(summary: dict[str, Any], indent: int | None = None) -> str:
    """Strict JSON of a summary: a quantity that is not a finite number (a compile time
    not measured, a strain without bristles drawn) is null, not NaN."""
    from bristlecrawler.io.jsonio import dumps_strict

    return dumps_strict(summary, indent=indent)


#: Energy-balance residual (of the connector work) above which a run is flagged. The paper
#: runs close to 7-9 %: HHT's algorithmic loss when a tip drops into a groove.
BALANCE_WARN = 0.2
#: Newton tolerance above which a run is flagged (default 1e-8; looser ones moved the
#: paper gait's advance by about 10 %).
TOLERANCE_WARN = 1e-6


def quality_warnings(balance: float, sc: Scenario) -> list[str]:
    """Warnings for a run whose convergence indicators are out of their normal range."""
    out = []
    if not balance <= BALANCE_WARN:
        out.append(
            f"energy balance residual {balance:.0%} of the connector work (normal: below "
            f"{BALANCE_WARN:.0%}); the gait may not be trustworthy (contact.mu = "
            f"{sc.contact.mu:g}, solver.tolerance = {sc.solver.tolerance:g})"
        )
    if sc.solver.tolerance > TOLERANCE_WARN:
        out.append(
            f"solver.tolerance = {sc.solver.tolerance:g} is looser than {TOLERANCE_WARN:g}: "
            "the gait can depend on it; check with a tighter one"
        )
    return out


def summarize(h: CrawlerHistory, sc: Scenario) -> dict[str, Any]:
    """Summary numbers (units in the key names): :meth:`CrawlerHistory.summary`, with the
    warnings of a run whose balance residual or tolerance is out of its normal range."""
    summary = h.summary()
    return summary.with_warnings(quality_warnings(h.energy_balance_rel_error(), sc)).to_dict()


def frame_subset(h: CrawlerHistory, per_cycle: int) -> np.ndarray:
    """Indices of about ``per_cycle`` frames per cycle, evenly spaced in time."""
    span = float(h.frame_t[-1] - h.frame_t[0])
    period = h.period or span / max(h.cycles, 1)
    n = max(round(per_cycle * span / period), 1) + 1
    targets = np.linspace(h.frame_t[0], h.frame_t[-1], n)
    idx = np.clip(np.searchsorted(h.frame_t, targets), 0, h.frame_t.size - 1)
    return np.unique(idx)


def solve(spec, progress: bool | None = None) -> CrawlerHistory:
    """Build and run ``spec`` with progress on stderr (None: bars on a terminal, lines
    otherwise); the compilation is announced with its expected time, and its measured
    time kept for the next estimate."""
    from bristlecrawler.crawler import build, run
    from bristlecrawler.jobs.estimates import Preparation
    from bristlecrawler.viz.progress import sim_progress

    prep = Preparation(spec)
    crawler = build(spec)
    t_end = spec.actuation.settle_time + spec.actuation.stroke_duration(spec.segments)
    notes = {"compiling": prep.stage_note()}
    with sim_progress(t_end, "crawler", progress, notes=notes) as bar:

        def show(p):
            bar.update(p.t, stage=p.stage, steps=p.steps, iters=p.iterations)

        h = run(crawler, on_progress=show)
    prep.finish(h.stats)
    return h


def run_simulation(
    sc: Scenario,
    out: str | Path | None = None,
    write: bool = True,
    progress: bool | None = None,
    command: str = "",
    replace: bool = False,
    on_start: Callable[[], None] | None = None,
    estimate: str | None = None,
) -> SimulationRun:
    """Run scenario ``sc``; with ``write``, put the results in ``out`` (see the module).

    The folder is claimed before the solve and appears complete or not at all
    (:func:`bristlecrawler.io.runs.claim_run_dir`; ``replace`` replaces a run already there).
    ``on_start`` is called once every input is checked and the folder claimed. The run's
    first line says how long it should take: from its last run here, else from
    ``estimate`` (the a-priori estimate of :mod:`bristlecrawler.scenario.cost`).
    """
    from bristlecrawler.scenario.convert import to_spec

    spec = to_spec(sc)  # reads and checks a history file, checks the design: before any work
    if not write:
        _started(on_start)
        h = solve(spec, progress)
        return SimulationRun(h, summarize(h, sc), None)

    from bristlecrawler.io.costs import record
    from bristlecrawler.io.runs import claim_run_dir
    from bristlecrawler.jobs.estimates import (
        expected,
        run_seconds,
        scenario_key,
        unmeasured,
    )
    from bristlecrawler.viz.progress import announce

    key = scenario_key("simulate", sc.model_dump(mode="json"))
    with claim_run_dir(out, f"simulate-{sc.name}", replace=replace, command=command) as run:
        _started(on_start)
        if progress is not False:
            first = unmeasured("run of this scenario", estimate)
            announce("crawler", f"results go to {run.target}; {expected('simulate', key, first)}")
        t0 = time.perf_counter()
        h = solve(spec, progress)
        summary = summarize(h, sc) | {"output_dir": str(run.target)}
        if progress is not False:  # drawing the figures and the animation takes a while
            import sys

            line = printable(f"crawler: writing results to {run.target}")
            print(line, file=sys.stderr, flush=True)
        _write_results(run, h, sc, command)
        run.write_json("summary.json", summary)
        record("simulate", key, run_seconds(time.perf_counter() - t0, h.stats))
    return SimulationRun(h, summary, run.target, tuple(run.notes))


def _write_results(run, h: CrawlerHistory, sc: Scenario, command: str) -> None:
    """Everything but the summary into the claimed folder ``run``."""
    from bristlecrawler.io.atomic import atomic_write_text
    from bristlecrawler.io.netcdf import write_netcdf
    from bristlecrawler.io.runs import config_json
    from bristlecrawler.scenario.keys import scenario_toml

    out_dir = run.path
    config = sc.model_dump(mode="json")
    info = run.write_metadata(config, command)
    keep = frame_subset(h, sc.output.frames_per_cycle)
    framed = dataclasses.replace(h, frame_t=h.frame_t[keep], frame_nodes=h.frame_nodes[keep])
    attrs = info.as_dict() | {"scenario": config_json(config, indent=None)}
    ds = framed.to_dataset(attrs=attrs)
    atomic_write_text(out_dir / "scenario.toml", scenario_toml(sc))
    write_netcdf(ds, out_dir / "crawler.nc")
    run.results_written("crawler.nc")
    if sc.output.vtk:
        from bristlecrawler.io.vtk import write_vtk_series

        kind = np.broadcast_to(framed.line_kind, (keep.size, framed.lines.shape[0]))
        point_data = None
        if framed.node_thickness is not None:  # mm, for ParaView's glyphs or tubes
            shape = (keep.size, framed.node_thickness.size)
            point_data = {"thickness": np.broadcast_to(framed.node_thickness, shape)}
        write_vtk_series(
            out_dir / "vtk",
            framed.frame_t,
            framed.frame_nodes,
            framed.lines,
            point_data=point_data,
            cell_data={"kind": kind},
        )
    if sc.output.figures:
        from bristlecrawler.viz.crawler import plot_connector, plot_delta_vs_s, plot_shapes
        from bristlecrawler.viz.reduced import save_figure

        title = f"{sc.name}: alpha = {sc.bristle.alpha_deg:g} deg, net {h.net_advance:.2f} mm"
        save_figure(plot_delta_vs_s(h, title=title), out_dir / "delta_vs_s.png")
        save_figure(plot_shapes(h), out_dir / "shapes.png")
        save_figure(plot_connector(h), out_dir / "connector.png")
    if sc.output.animation:
        from bristlecrawler.viz.crawler import animate

        animate(framed, out_dir / "crawler")


def _started(on_start: Callable[[], None] | None) -> None:
    if on_start is not None:
        on_start()
