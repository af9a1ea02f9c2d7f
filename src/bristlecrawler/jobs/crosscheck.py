"""``bristlecrawler crosscheck drag``: the drag test in CalculiX beside the toolkit's own.

One leg along the grain, one pitch long, from a tip that starts in the middle of a
groove's bottom (the grooves are shifted for it; other substrates as they are): the tip
sticks, then the bristle is held by the groove's far wall and its corner until it climbs
out, then slides on the next land. Both codes run the same design and path: CalculiX the
continuum deck of :mod:`export.drag_deck` (quasi-static), the toolkit its dynamic beam
model (:func:`crawler.drag.drag_test`). The rows (:mod:`export.compare`) are read from
both series the same way.

Output folder (``runs/<timestamp>-crosscheck-<name>`` unless given): ``config.json``,
``meta.json``, the deck and CalculiX's files (``drag_continuum.inp``, ``.dat``, ``.log``,
``.frd``), ``crosscheck.json`` (the rows, both runs' facts), ``crosscheck.md`` (the
table) and ``crosscheck.png`` (force against travel, both codes).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

#: Where the tip starts across the groove's bottom, from its left wall (a fraction).
START_SHARE = 0.5


@dataclass(frozen=True)
class CrosscheckRun:
    """A finished cross-check: its rows, the facts of both runs and the folder."""

    rows: list
    facts: dict[str, Any]
    out_dir: Path | None


def crosscheck_test(spec):
    """The cross-check's drag test: one leg along the grain, one pitch (at least 1 mm)."""
    from bristlecrawler.crawler.drag import DragTest
    from bristlecrawler.crawler.drag_analysis import substrate_pitch

    return DragTest(direction="along", distance=max(substrate_pitch(spec), 1.0))


def prepare(spec, plane: str = "stress"):
    """The shifted design, the test and the CalculiX deck (checked; InputError on a spec
    the deck cannot express), before anything runs."""
    from bristlecrawler.export import ContinuumOptions, continuum_deck, crosscheck_spec

    test = crosscheck_test(spec)
    cspec = crosscheck_spec(spec, test, START_SHARE)
    text, info = continuum_deck(cspec, test, ContinuumOptions(plane=plane))
    return cspec, test, text, info


def series_from_calculix(printed, info):
    """The drag leg of CalculiX's printed results (from the end of the load step)."""
    from bristlecrawler.export.compare import DragSeries

    force = printed[("total force", "CLAMP")]
    u = printed[("displacements", "CARRIAGE")]
    sub = printed[("total force", "SUBSTRATE_NODES")]
    keep = force.time >= info.settle - 1e-12
    return DragSeries(
        x=u.values[keep, 0, 0],
        force=force.values[keep, 0, 0],
        contact=-sub.values[keep, 0, :2],
    )


def series_from_toolkit(result):
    from bristlecrawler.export.compare import DragSeries

    return DragSeries(x=result.x, force=result.force_x, contact=result.contact)


def run_crosscheck(
    sc,
    plane: str = "stress",
    out: str | Path | None = None,
    progress: bool | None = None,
    command: str = "",
    replace: bool = False,
    on_start: Callable[[], None] | None = None,
) -> CrosscheckRun:
    """Run the cross-check of scenario ``sc``'s first bristle and write its folder."""
    from bristlecrawler.export.ccx import find_ccx, run_ccx
    from bristlecrawler.export.compare import compare
    from bristlecrawler.io.runs import claim_run_dir
    from bristlecrawler.jobs.drag import solve_drag
    from bristlecrawler.scenario.convert import to_spec

    spec = to_spec(sc)
    cspec, test, text, info = prepare(spec, plane)
    exe = find_ccx()
    with claim_run_dir(out, f"crosscheck-{sc.name}", replace=replace, command=command) as run:
        if on_start is not None:
            on_start()
        config = {
            "scenario": sc.model_dump(mode="json"),
            "drag": dataclasses.asdict(test),
            "plane": plane,
            "substrate_phase_mm": _phase(cspec),
        }
        run.write_metadata(config, command)
        (run.path / "drag_continuum.inp").write_text(text, encoding="ascii")
        ccx = run_ccx(run.path, "drag_continuum", exe=exe)
        result = solve_drag(cspec, test, progress)
        rows = compare(
            series_from_toolkit(result), series_from_calculix(ccx.printed, info), cspec.contact.mu
        )
        facts = {
            "calculix_version": ccx.version,
            "calculix_complete": ccx.complete,
            "calculix_stopped": ccx.stopped,
            "calculix_wall_s": ccx.wall_s,
            "plane": plane,
            "load_N": info.load,
            "bristle_weight_N": info.bristle_weight,
            "mu": cspec.contact.mu,
        }
        run.write_json("crosscheck.json", {"rows": [r.to_dict() for r in rows], **facts})
        run.results_written("crosscheck.json")
        (run.path / "crosscheck.md").write_text(table_markdown(rows))
        _figure(result, ccx, info, run.path / "crosscheck.png", sc.name, plane)
    return CrosscheckRun(rows, facts, run.target)


def _phase(spec) -> float | None:
    phase = getattr(spec.substrate, "phase", None)
    return None if phase is None else float(phase)


def table_markdown(rows) -> str:
    """The rows as a Markdown table (numbers to 4 digits, the difference in %)."""
    lines = [
        "| quantity | toolkit | CalculiX | difference | expected | note |",
        "|---|---|---|---|---|---|",
    ]
    for r in rows:
        exp = "" if math.isnan(r.expected) else f"{r.expected:.4g} {r.unit}"
        diff = "" if math.isnan(r.difference) else f"{100 * r.difference:+.1f} %"
        cells = (f"{r.quantity} ({r.unit})", f"{r.toolkit:.4g}", f"{r.calculix:.4g}", diff, exp)
        lines.append("| " + " | ".join((*cells, r.note)) + " |")
    return "\n".join(lines) + "\n"


def _figure(result, ccx, info, path: Path, name: str, plane: str) -> None:
    from bristlecrawler.viz.crosscheck import plot_crosscheck
    from bristlecrawler.viz.reduced import save_figure

    c = series_from_calculix(ccx.printed, info)
    fig = plot_crosscheck(
        (np.asarray(result.x), np.asarray(result.force_x)),
        (c.x, c.force),
        labels=("bristlecrawler (beam, dynamic)", f"CalculiX (plane {plane}, static)"),
        title=f"{name}: drag test, one pitch along the grain",
    )
    save_figure(fig, path)
