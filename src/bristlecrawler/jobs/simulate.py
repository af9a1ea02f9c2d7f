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

from bristlecrawler.crawler.history import STRAIN_LIMIT, CrawlerHistory
from bristlecrawler.errors import InputError
from bristlecrawler.scenario.schema import Scenario


@dataclass(frozen=True)
class SimulationRun:
    """A finished FE crawler run: its history, summary and output folder."""

    history: CrawlerHistory
    summary: dict[str, Any]
    out_dir: Path | None


def apply_overrides(sc: Scenario, assignments: list[str]) -> Scenario:
    """The scenario with ``section.key=value`` assignments (TOML values) applied and
    re-validated; a bad assignment raises a one-line InputError."""
    import tomllib

    values = {}
    for item in assignments:
        key, sep, raw = item.partition("=")
        if not sep or not key.strip():
            raise InputError(f"--set expects section.key=value, got {item!r}")
        try:
            value = tomllib.loads(f"v = {raw.strip()}")["v"]
        except tomllib.TOMLDecodeError:
            value = raw.strip()  # bare words (kind = grooves) are strings
        values[key.strip()] = value
    return apply_values(sc, values)


def apply_values(sc: Scenario, values: dict[str, Any]) -> Scenario:
    """The scenario with ``{"section.key": value}`` set (Python values, e.g. a path as
    it is) and re-validated; an unknown key or a bad value raises a one-line InputError.
    Setting ``substrate.kind`` to another kind starts that table afresh (its ``mu`` kept),
    so the new kind's keys follow it."""
    from bristlecrawler.scenario.load import scenario_from_dict

    data = sc.model_dump()
    for key, value in values.items():
        *path, last = key.split(".")
        if path == ["substrate"] and last == "kind" and value != data["substrate"]["kind"]:
            # Another kind of texture: none of the old kind's keys apply (its mu does).
            data["substrate"] = {"kind": value, "mu": data["substrate"]["mu"]}
            continue
        node = data
        for part in path:
            if not isinstance(node.get(part), dict):
                raise InputError(f"--set {key}: unknown section {part!r}")
            node = node[part]
        if last not in node and path != ["substrate"]:  # the substrate's kind checks its keys
            raise InputError(f"--set {key}: unknown parameter {last!r}")
        node[last] = value
    return scenario_from_dict(data, "scenario (with --set)")


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


def summarize(h: CrawlerHistory, sc: Scenario) -> dict[str, Any]:
    """Summary numbers (units in the key names)."""
    adv = h.advance_per_cycle()
    work = h.connector_work
    b = h.cycle_bounds()
    st = h.stats
    peak = h.strain_peak()
    warnings = []
    if peak is not None and peak.strain > STRAIN_LIMIT:
        warnings.append(peak.message())
    return {
        "scenario": sc.name,
        "net_advance_mm": h.net_advance,
        "advance_per_cycle_mm": adv.tolist(),
        "work_mJ": float(work[-1]),
        "work_per_cycle_mJ": np.diff(work[b]).tolist(),
        "mean_abs_connector_force_N": float(
            np.trapezoid(np.abs(h.connector_force), h.t) / max(h.t[-1] - h.t[0], 1e-300)
        ),
        "max_abs_connector_force_N": float(np.max(np.abs(h.connector_force))),
        "energy_balance_rel_error": h.energy_balance_rel_error(),
        "friction_dissipation_mJ": float(h.energies.get("friction", [0.0])[-1]),
        "damping_dissipation_mJ": float(h.energies.get("damping", [0.0])[-1]),
        "wall_time_s": float(st.get("wall_time_s", float("nan"))),
        "compile_time_s": float(st.get("compile_time_s", float("nan"))),
        "stroke_wall_time_s": float(st.get("stroke_wall_time_s", float("nan"))),
        "steps": int(st.get("steps", h.t.size - 1)),
        "newton_iterations": int(st.get("newton_iterations", 0)),
        "rejected_steps": int(st.get("rejected_steps", 0)),
        "first_frequency_hz": float(st.get("first_frequency_hz", float("nan"))),
        "rayleigh_a0_per_s": float(st.get("rayleigh_a0", float("nan"))),
        "max_bristle_strain": float("nan") if peak is None else peak.strain,
        "warnings": warnings,
    }


def frame_subset(h: CrawlerHistory, per_cycle: int) -> np.ndarray:
    """Indices of about ``per_cycle`` frames per cycle, evenly spaced in time."""
    span = float(h.frame_t[-1] - h.frame_t[0])
    period = h.period or span / max(h.cycles, 1)
    n = max(round(per_cycle * span / period), 1) + 1
    targets = np.linspace(h.frame_t[0], h.frame_t[-1], n)
    idx = np.clip(np.searchsorted(h.frame_t, targets), 0, h.frame_t.size - 1)
    return np.unique(idx)


def run_simulation(
    sc: Scenario,
    out: str | Path | None = None,
    write: bool = True,
    progress: bool | None = None,
    command: str = "",
) -> SimulationRun:
    """Run scenario ``sc``; with ``write``, put the results in ``out`` (see the module)."""
    from bristlecrawler.crawler import run as crawler_run
    from bristlecrawler.crawler.model import stroke_duration
    from bristlecrawler.io.runs import check_out_dir

    stroke_duration(sc)  # reads and checks a history file before any work
    if write:
        check_out_dir(out)
    h = crawler_run.simulate_crawler(sc, crawler_run.RunOptions(progress=progress))
    summary = summarize(h, sc)
    if not write:
        return SimulationRun(h, summary, None)

    from bristlecrawler.io.atomic import atomic_write_text
    from bristlecrawler.io.crawler_dataset import crawler_dataset
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
    ds = crawler_dataset(framed, attrs=attrs)
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
