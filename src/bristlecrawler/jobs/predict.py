"""The ``bristlecrawler predict`` job: the reduced models of a scenario, before any FE run.

A drag test of the scenario's bristle over its substrate (back and forth over whole
pitches) gives the paper's parameters (k, F_p, F_n) and the texture law (k, F_p(x),
F_n(x)); both reduced crawlers then play the scenario's actuation. Drag tests cost minutes,
so their summaries are kept in a cache folder (``$BRISTLECRAWLER_DRAG_CACHE``, default
``~/.cache/bristlecrawler/drag``), one JSON file per bristle and texture, keyed by every
scenario value the drag test reads; written atomically, and an unreadable entry is run
again.
"""

from __future__ import annotations

import hashlib
import json
import os
from dataclasses import asdict
from pathlib import Path
from typing import Any

from bristlecrawler.reduced.drag_summary import FN_N, FP_N, K_N_PER_MM, DragSummary
from bristlecrawler.reduced.metrics import RunMetrics

#: Bump when the drag test or its analysis changes what a cached summary holds.
CACHE_VERSION = 2
#: Scenario sections a drag test reads (the actuation only for its settle time).
_DRAG_SECTIONS = ("body", "bristle", "substrate", "contact", "damping", "solver", "gravity")


def cache_folder() -> Path:
    """Where drag summaries are kept: ``$BRISTLECRAWLER_DRAG_CACHE`` or
    ``$XDG_CACHE_HOME/bristlecrawler/drag`` (``~/.cache/...``)."""
    path = os.environ.get("BRISTLECRAWLER_DRAG_CACHE")
    if path:
        return Path(path).expanduser()
    base = Path(os.environ.get("XDG_CACHE_HOME", Path.home() / ".cache"))
    return base / "bristlecrawler" / "drag"


def prediction_drag_test(spec):
    """The drag test a prediction needs: back and forth over at least two pitches
    (8 mm or more), at the default speed and the bristle's weight share."""
    from bristlecrawler.crawler.drag import DragTest
    from bristlecrawler.crawler.drag_analysis import substrate_pitch

    return DragTest(direction="cycle", distance=max(8.0, 2.0 * substrate_pitch(spec)))


def cache_key(sc, test) -> str:
    """Hash of what decides a drag test's result: the scenario's bristle, body (the load),
    substrate, contact, damping, solver, gravity and settle time, and the test."""
    data = sc.model_dump(mode="json")
    keyed = {k: data.get(k) for k in _DRAG_SECTIONS}
    keyed["settle_time"] = data.get("actuation", {}).get("settle_time")
    keyed["test"] = asdict(test)
    keyed["version"] = CACHE_VERSION
    text = json.dumps(keyed, sort_keys=True, separators=(",", ":"))
    return hashlib.sha256(text.encode()).hexdigest()[:32]


def cached_drag(sc, test, progress: bool | None = False) -> tuple[DragSummary, bool]:
    """The drag summary for ``sc`` and ``test`` from the cache, or run and stored.
    Returns (summary, whether it came from the cache)."""
    from bristlecrawler.io.atomic import atomic_write_text
    from bristlecrawler.io.jsonio import dumps_strict

    path = cache_folder() / f"{cache_key(sc, test)}.json"
    try:
        entry = json.loads(path.read_text())
        if entry.get("version") == CACHE_VERSION and isinstance(entry["summary"]["texture"], dict):
            return DragSummary.from_dict(entry["summary"]), True
    except (OSError, ValueError, KeyError, TypeError):
        pass  # missing or unreadable: run it again
    from bristlecrawler.jobs.drag import run_drag

    run = run_drag(sc, test, write=False, progress=progress)
    summary = {k: v for k, v in run.summary.items() if k != "output_dir"}
    if summary.get("texture") is None:
        from bristlecrawler.errors import SolverError

        raise SolverError("the drag test did not slide both ways: no texture law")
    try:
        atomic_write_text(path, dumps_strict({"version": CACHE_VERSION, "summary": summary}))
    except OSError:
        pass  # a read-only cache only costs the next run its drag test
    return DragSummary.from_dict(summary), False


def predict_models(
    spec, summary: DragSummary | dict, cycles: int, paper: bool = True
) -> dict[str, RunMetrics]:
    """The texture model and (with ``paper``) the paper's model of ``spec`` with a drag
    ``summary`` (typed or its JSON mapping)."""
    import numpy as np

    from bristlecrawler.crawler.prediction import reduced_gait, reduced_twin
    from bristlecrawler.reduced import simulate
    from bristlecrawler.reduced.textured import TexturedCrawler

    x = np.sort([b.position for b in spec.bristles])
    crawlers = {
        "texture": TexturedCrawler.from_drag(
            summary, len(x), segment_lengths=np.diff(x), start_mm=float(x[0])
        )
    }
    if paper:
        crawlers["paper"] = reduced_twin(spec, summary)
    out = {}
    for name, crawler in crawlers.items():
        r = simulate(crawler, reduced_gait(spec), cycles=cycles, samples_per_cycle=400)
        out[name] = RunMetrics.from_reduced(r)
    return out


def run_predict(sc, cycles: int | None = None, progress: bool | None = False) -> dict[str, Any]:
    """Checks (one-line InputError), drag test (cached), both models: a JSON-ready dict.

    Each model's entry under ``models`` says what it assumed, and why it was not run where
    it does not apply (``paper`` is then None); ``disagreement`` is the line for models
    that differ by more than a pitch per cycle (see :mod:`bristlecrawler.jobs.predict_report`).
    """
    import math

    from bristlecrawler.jobs.predict_report import (
        LABELS,
        assumptions,
        disagreement,
        paper_model_refusal,
    )
    from bristlecrawler.scenario.convert import to_spec

    spec = to_spec(sc)
    test = prediction_drag_test(spec)
    spec.check()  # the design's and the test's checks, before minutes of drag test
    test.check(spec)
    cycles = cycles or spec.actuation.cycles
    summary, hit = cached_drag(sc, test, progress)
    scatter = summary.along.scatter if summary.along else math.nan
    refused = {"paper": paper_model_refusal(summary.fp, summary.fn, scatter)}
    models = predict_models(spec, summary, cycles, paper=refused["paper"] is None)
    law = summary.texture
    results = {name: (models[name].to_dict() if name in models else None) for name in LABELS}
    assumed = assumptions(summary, cycles, len(spec.bristles))
    return {
        "scenario": sc.name,
        "cycles": cycles,
        **results,
        "models": {
            name: {"label": label, "assumes": assumed[name], "not_run": refused.get(name)}
            for name, label in LABELS.items()
        },
        "disagreement": disagreement(
            results["texture"], results["paper"], law.pitch_mm, len(spec.bristles)
        ),
        "drag": {
            "cached": hit,
            K_N_PER_MM: summary.k,
            FP_N: summary.fp,
            FN_N: summary.fn,
            "pitch_mm": law.pitch_mm,
            "lock_positions_mm": law.lock_positions_mm.tolist(),
        },
    }
