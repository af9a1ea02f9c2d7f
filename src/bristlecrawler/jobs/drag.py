"""The ``bristlecrawler drag`` job: a virtual drag test of a scenario's bristle.

Output folder (``runs/<timestamp>-drag-<name>`` unless given): ``config.json`` (the
resolved scenario and the test), ``meta.json``, ``drag.nc`` (the series, xarray/NetCDF),
``drag.png`` (force against carriage travel, the sliding means marked), ``texture.png``
(the texture law over one pitch, for a test that slid both ways) and ``summary.json``
(k, F_p, F_n with their scatter and peaks, dissipation per mm, the texture law).
"""

from __future__ import annotations

import dataclasses
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any


@dataclass(frozen=True)
class DragRun:
    """A finished drag test: its result, summary and output folder."""

    result: Any
    summary: dict[str, Any]
    out_dir: Path | None


def solve_drag(spec, test, progress: bool | None = None):
    """Run the drag test with progress on stderr (None: bars on a terminal, lines
    otherwise), its compilation announced with the expected time."""
    from bristlecrawler.crawler.drag import drag_test
    from bristlecrawler.jobs.estimates import Preparation
    from bristlecrawler.viz.progress import sim_progress

    t_end = spec.actuation.settle_time + test.duration
    prep = Preparation(spec, "drag")
    notes = {"compiling": prep.stage_note()}
    with sim_progress(t_end, "drag test", progress, notes=notes) as bar:

        def show(p):
            bar.update(p.t, stage=p.stage, steps=p.steps, iters=p.iterations)

        r = drag_test(spec, test, on_progress=show)
    prep.finish(r.stats)
    return r


def run_drag(
    sc,
    test,
    out: str | Path | None = None,
    write: bool = True,
    progress: bool | None = None,
    command: str = "",
    replace: bool = False,
    on_start: Callable[[], None] | None = None,
    estimate: str | None = None,
) -> DragRun:
    """Run the drag test of scenario ``sc``; with ``write``, put the results in ``out``.
    ``on_start`` is called once every input is checked and the folder claimed; the first
    line's expected time comes from the last such test here, else from ``estimate``."""
    from bristlecrawler.crawler.drag import build_drag
    from bristlecrawler.scenario.convert import to_spec

    spec = to_spec(sc)
    build_drag(spec, test)  # the test's checks, before any folder is claimed
    if not write:
        _started(on_start)
        r = solve_drag(spec, test, progress)
        return DragRun(r, r.summary(), None)

    from bristlecrawler.io.costs import record
    from bristlecrawler.io.netcdf import write_netcdf
    from bristlecrawler.io.runs import claim_run_dir
    from bristlecrawler.jobs.estimates import (
        expected,
        run_seconds,
        scenario_key,
        unmeasured,
    )
    from bristlecrawler.viz.progress import announce

    key = scenario_key("drag", {"scenario": sc.model_dump(mode="json"), "test": repr(test)})
    with claim_run_dir(out, f"drag-{sc.name}", replace=replace, command=command) as run:
        _started(on_start)
        if progress is not False:
            first = unmeasured("drag test of this scenario", estimate)
            announce("drag test", f"results go to {run.target}; {expected('drag', key, first)}")
        t0 = time.perf_counter()
        r = solve_drag(spec, test, progress)
        config = {"scenario": sc.model_dump(mode="json"), "drag": dataclasses.asdict(test)}
        run.write_metadata(config, command)
        write_netcdf(r.to_dataset(), run.path / "drag.nc")
        run.results_written("drag.nc")
        from bristlecrawler.viz.drag import plot_drag
        from bristlecrawler.viz.reduced import save_figure

        save_figure(plot_drag(r, title=f"{sc.name}: drag test"), run.path / "drag.png")
        law = r.texture()
        if law is not None:
            from bristlecrawler.crawler.drag_texture import reduced_tip
            from bristlecrawler.viz.drag import plot_texture

            tip = (reduced_tip(r, law.k_N_per_mm), r.force_x)
            fig = plot_texture(law, tip, title=f"{sc.name}: texture law over one pitch")
            save_figure(fig, run.path / "texture.png")
        summary = r.summary() | {"output_dir": str(run.target)}
        run.write_json("summary.json", summary)
        record("drag", key, run_seconds(time.perf_counter() - t0, r.stats))
    return DragRun(r, summary, run.target)


def _started(on_start: Callable[[], None] | None) -> None:
    if on_start is not None:
        on_start()
