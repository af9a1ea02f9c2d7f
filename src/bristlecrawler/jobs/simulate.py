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
import json
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from bristlecrawler.crawler.history import CrawlerHistory
from bristlecrawler.scenario.schema import Scenario


@dataclass(frozen=True)
class SimulationRun:
    """A finished FE crawler run: its history, summary and output folder."""

    history: CrawlerHistory
    summary: dict[str, Any]
    out_dir: Path | None


def summary_json(summary: dict[str, Any], indent: int | None = None) -> str:
    """Strict JSON of a summary: a quantity that is not a finite number (a compile time
    not measured, a strain without bristles drawn) is null, not NaN."""

    def clean(v):
        if isinstance(v, float) and not math.isfinite(v):
            return None
        if isinstance(v, list):
            return [clean(x) for x in v]
        return v

    return json.dumps({k: clean(v) for k, v in summary.items()}, indent=indent, allow_nan=False)


def summarize(h: CrawlerHistory, sc: Scenario | None = None) -> dict[str, Any]:
    """Summary numbers (units in the key names): :meth:`CrawlerHistory.summary`."""
    return h.summary()


def frame_subset(h: CrawlerHistory, per_cycle: int) -> np.ndarray:
    """Indices of about ``per_cycle`` frames per cycle, evenly spaced in time."""
    span = float(h.frame_t[-1] - h.frame_t[0])
    period = h.period or span / max(h.cycles, 1)
    n = max(round(per_cycle * span / period), 1) + 1
    targets = np.linspace(h.frame_t[0], h.frame_t[-1], n)
    idx = np.clip(np.searchsorted(h.frame_t, targets), 0, h.frame_t.size - 1)
    return np.unique(idx)


def solve(spec, progress: bool | None = None) -> CrawlerHistory:
    """Build and run ``spec`` with a progress bar on stderr (None: when it is a terminal)."""
    from bristlecrawler.crawler import build, run
    from bristlecrawler.viz.progress import sim_progress

    crawler = build(spec)
    t_end = spec.actuation.settle_time + spec.actuation.stroke_duration(spec.segments)
    with sim_progress(t_end, "crawler", progress) as bar:

        def show(p):
            bar.update(p.t, stage=p.stage, steps=p.steps, iters=p.iterations)

        return run(crawler, on_progress=show)


def run_simulation(
    sc: Scenario,
    out: str | Path | None = None,
    write: bool = True,
    progress: bool | None = None,
    command: str = "",
) -> SimulationRun:
    """Run scenario ``sc``; with ``write``, put the results in ``out`` (see the module)."""
    from bristlecrawler.io.runs import check_out_dir
    from bristlecrawler.scenario.convert import to_spec

    spec = to_spec(sc)  # reads and checks a history file, checks the design: before any work
    if write:
        check_out_dir(out)
    h = solve(spec, progress)
    summary = h.summary()
    if not write:
        return SimulationRun(h, summary, None)

    from bristlecrawler.io.atomic import atomic_write_text
    from bristlecrawler.io.netcdf import write_netcdf
    from bristlecrawler.io.runs import config_json, prepare_run_dir, write_run_metadata
    from bristlecrawler.scenario.keys import scenario_toml

    out_dir = prepare_run_dir(out, f"simulate-{sc.name}")
    if progress is not False:  # drawing the figures and the animation takes a while
        import sys

        print(f"crawler: writing results to {out_dir}", file=sys.stderr, flush=True)
    config = sc.model_dump(mode="json")
    info = write_run_metadata(out_dir, config, command)
    keep = frame_subset(h, sc.output.frames_per_cycle)
    framed = dataclasses.replace(h, frame_t=h.frame_t[keep], frame_nodes=h.frame_nodes[keep])
    attrs = info.as_dict() | {"scenario": config_json(config, indent=None)}
    ds = framed.to_dataset(attrs=attrs)
    atomic_write_text(out_dir / "scenario.toml", scenario_toml(sc))
    write_netcdf(ds, out_dir / "crawler.nc")
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
    summary = summary | {"output_dir": str(out_dir)}
    atomic_write_text(out_dir / "summary.json", summary_json(summary, indent=2) + "\n")
    return SimulationRun(h, summary, out_dir)
