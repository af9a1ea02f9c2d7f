"""The ``bristlecrawler predict`` job: the reduced models of a scenario, before any FE run.

The bristled model (:mod:`bristlecrawler.reduced.bristled`) needs no FE and is the
default. A drag test of the scenario's bristle over its substrate (back and forth over whole
pitches) gives the paper's parameters (k, F_p, F_n) and the texture law (k, F_p(x),
F_n(x)); both reduced crawlers then play the scenario's actuation. Drag tests cost minutes,
so their summaries are kept in a cache folder (``$BRISTLECRAWLER_DRAG_CACHE``, default
``~/.cache/bristlecrawler/drag``), one JSON file per bristle and texture, keyed by every
scenario value the drag test reads; written atomically as ``0600`` files in a ``0700``
folder. An entry that is not a regular file of the user's that no one else may write, or
not a drag summary, is run again (one warning); a folder that another user owns, or that
group or others may write, is not used.
"""

from __future__ import annotations

import hashlib
import json
import os
from dataclasses import asdict
from pathlib import Path
from typing import Any

from bristlecrawler.results.drag import DragSummary
from bristlecrawler.results.keys import FN_N, FP_N, K_N_PER_MM
from bristlecrawler.results.metrics import RunMetrics

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
    from bristlecrawler._files import xdg_home

    return xdg_home("XDG_CACHE_HOME", ".cache") / "bristlecrawler" / "drag"


def prediction_drag_test(spec):
    """The drag test a prediction needs: back and forth over at least two pitches
    (8 mm or more), at the default speed and the bristle's weight share."""
    from bristlecrawler.crawler.drag import DragTest

    return DragTest(direction="cycle", distance=max(8.0, 2.0 * spec.substrate.period))


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
    from bristlecrawler._files import untrusted_folder

    folder = cache_folder()
    path = folder / f"{cache_key(sc, test)}.json"
    distrust = untrusted_folder(folder)
    if distrust is not None:
        _warn(f"{distrust}; its drag tests are neither read nor stored (chmod 700 it)")
    else:
        summary = _read_entry(path)
        if summary is not None:
            return summary, True
    from bristlecrawler.jobs.drag import run_drag

    run = run_drag(sc, test, write=False, progress=progress)
    summary = {k: v for k, v in run.summary.items() if k != "output_dir"}
    if summary.get("texture") is None:
        from bristlecrawler.errors import SolverError

        raise SolverError("the drag test did not slide both ways: no texture law")
    if distrust is None:
        _write_entry(path, summary)
    return DragSummary.from_dict(summary), False


#: The largest drag-cache entry read (one is a few kB).
MAX_ENTRY_BYTES = 1 << 20


def _read_entry(path: Path) -> DragSummary | None:
    """The summary a cache entry holds, or None: absent, or (with one warning) not a
    regular file of the user's that no one else may write, or not an entry's shape."""
    from bristlecrawler._files import read_own

    try:
        entry = json.loads(read_own(path, MAX_ENTRY_BYTES))
    except FileNotFoundError:
        return None
    except (OSError, ValueError) as exc:
        _warn(f"drag-cache entry {path.name} not used ({_why(exc)}); running the drag test")
        return None
    try:
        if entry["version"] != CACHE_VERSION:
            return None  # written by another version: run again and replace
        summary = entry["summary"]
        if not isinstance(summary["texture"], dict):
            raise TypeError("no texture law")
        out = DragSummary.from_dict(summary)
        if out.texture is None:
            raise TypeError("no texture law")
        return out
    except Exception as exc:  # any shape valid JSON can take (a list, a string, ...)
        _warn(
            f"drag-cache entry {path.name} not used (not a drag summary: {_why(exc)}); "
            "running the drag test"
        )
        return None


def _write_entry(path: Path, summary: dict) -> None:
    """Store ``summary`` at ``path`` (0600, folders 0700, atomically); a cache that
    cannot be written only costs the next run its drag test."""
    from bristlecrawler._files import write_private
    from bristlecrawler.io.jsonio import dumps_strict

    text = dumps_strict({"version": CACHE_VERSION, "summary": summary})
    try:
        write_private(path, text.encode())
    except OSError as exc:
        _warn(f"drag cache {path.parent} not written ({_why(exc)})")


def _why(exc: BaseException) -> str:
    return str(getattr(exc, "strerror", None) or exc or type(exc).__name__)[:200]


def _warn(message: str) -> None:
    import warnings

    from bristlecrawler.fe.program_store import CacheWarning

    warnings.warn(message, CacheWarning, stacklevel=3)


def predict_models(
    spec, summary: DragSummary, cycles: int, paper: bool = True
) -> dict[str, RunMetrics]:
    """The texture model and (with ``paper``) the paper's model of ``spec`` with a drag
    test's ``summary``."""
    import numpy as np

    from bristlecrawler.crawler.prediction import reduced_gait
    from bristlecrawler.reduced import simulate
    from bristlecrawler.reduced.model import ReducedModel

    x = np.sort([b.position for b in spec.bristles])
    crawlers = {
        name: ReducedModel.registered[name].from_drag(
            summary, len(x), segment_lengths=np.diff(x), start_mm=float(x[0])
        )
        for name in (("texture", "paper") if paper else ("texture",))
    }
    out = {}
    for name, crawler in crawlers.items():
        r = simulate(crawler, reduced_gait(spec), cycles=cycles, samples_per_cycle=400)
        out[name] = RunMetrics.from_reduced(r)
    return out


def bristled_result(spec, cycles: int) -> tuple[dict | None, str | None]:
    """The bristled model's metrics of ``spec`` (a JSON mapping), or None and why it was
    not run or did not settle."""
    from bristlecrawler.crawler.bristled import bristled_metrics
    from bristlecrawler.errors import InputError, SolverError

    try:
        return bristled_metrics(spec, cycles).to_dict(), None
    except (InputError, SolverError) as exc:
        return None, str(exc)


def run_predict(
    sc,
    cycles: int | None = None,
    progress: bool | None = False,
    drag: bool = True,
    bristled: bool = True,
) -> dict[str, Any]:
    """Checks (one-line InputError), the bristled model, then (with ``drag``) the drag
    test (cached) and the texture and paper models: a JSON-ready dict.

    ``default`` names the model whose numbers to use (the bristled model); each model's
    results are under its name, and its entry under ``models`` says what it assumed, where
    it was checked, and why it was not run where it does not apply (its results are then
    None); ``disagreement`` is the line for drag-test models that differ by more than a
    pitch per cycle (see :mod:`bristlecrawler.jobs.predict_report`).
    """
    import math

    from bristlecrawler.jobs.predict_report import (
        CHECKED,
        DEFAULT,
        LABELS,
        assumptions,
        bristled_assumptions,
        disagreement,
        paper_model_refusal,
    )
    from bristlecrawler.scenario.convert import to_spec
    from bristlecrawler.scenario.drag import drag_estimate

    spec = to_spec(sc)
    spec.check()
    cycles = cycles or spec.actuation.cycles
    if not (drag or bristled):
        from bristlecrawler.errors import InputError

        raise InputError("--no-drag and --no-bristled leave no model to run")
    test = prediction_drag_test(spec) if drag else None
    if drag:
        test.check(spec)  # the test's checks, before minutes of drag test
        # Refused as `drag` refuses it, cached or not: an entry for it cannot be honest.
        drag_estimate(sc, test).check()
    results = {name: None for name in LABELS}
    refused = {name: None for name in LABELS}
    if bristled:
        results[DEFAULT], refused[DEFAULT] = bristled_result(spec, cycles)
    else:
        refused[DEFAULT] = "not asked for (--no-bristled)"
    assumed = {DEFAULT: bristled_assumptions(spec, cycles)}
    out = {"scenario": sc.name, "cycles": cycles, "default": DEFAULT}
    if drag:
        summary, hit = cached_drag(sc, test, progress)
        scatter = summary.along.scatter if summary.along else math.nan
        refused["paper"] = paper_model_refusal(summary.fp, summary.fn, scatter)
        models = predict_models(spec, summary, cycles, paper=refused["paper"] is None)
        results.update({name: m.to_dict() for name, m in models.items()})
        assumed.update(assumptions(summary, cycles, len(spec.bristles)))
        law = summary.texture
        out["disagreement"] = disagreement(
            results["texture"], results["paper"], law.pitch_mm, len(spec.bristles)
        )
        out["drag"] = {
            "cached": hit,
            K_N_PER_MM: summary.k,
            FP_N: summary.fp,
            FN_N: summary.fn,
            "pitch_mm": law.pitch_mm,
            "lock_positions_mm": law.lock_positions_mm.tolist(),
        }
    else:
        why = "no drag test asked for (--no-drag): this model needs one"
        refused.update({name: why for name in LABELS if name != DEFAULT})
        out["disagreement"] = None
        out["drag"] = None
    out.update(results)
    out["models"] = {
        name: {
            "label": label,
            "assumes": assumed.get(name),
            "checked": CHECKED[name],
            "not_run": refused.get(name),
        }
        for name, label in LABELS.items()
    }
    return out
