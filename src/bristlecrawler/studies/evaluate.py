"""One design (fe) or a chunk of designs (reduced) in, the per-design outputs out.

A design that fails is a value (status FAILED and its message), not an exception: the
other designs of the study go on.
"""

from __future__ import annotations

import enum
import time
from typing import Any

import numpy as np

from bristlecrawler.results.metrics import DESIGN_OUTPUTS, DesignMetrics

#: name -> (unit, description); every design of every model gives all of them.
OUTPUTS: dict[str, tuple[str, str]] = DESIGN_OUTPUTS
INTEGER_OUTPUTS = ("steps", "newton_iterations")


class DesignStatus(enum.IntEnum):
    """State of a design in the store (one meaning across the package)."""

    PENDING = 0  # not evaluated yet (a sweep that was stopped)
    DONE = 1
    FAILED = 2  # the model refused or could not finish it: see its error message
    LOST = 3  # its task's worker died more often than the scheduler retries


def evaluate_fe(scenario: dict[str, Any]) -> dict[str, Any]:
    """Run one FE design (a scenario as a dict) and reduce its history to the outputs."""
    from bristlecrawler.crawler import run
    from bristlecrawler.scenario.convert import to_spec
    from bristlecrawler.scenario.load import scenario_from_dict

    sc = scenario_from_dict(scenario, "design")
    return _fe_outputs(run(to_spec(sc)), sc.actuation.cycles)


def _fe_outputs(history, cycles) -> dict[str, float]:
    metrics = DesignMetrics.from_summary(history.summary().to_dict(), cycles)
    return {k: float(v) for k, v in metrics.to_dict().items()}


def evaluate_fe_batch(scenarios: list[dict[str, Any]], width: int) -> list[dict[str, Any] | str]:
    """FE designs of one structure in one compiled program (:func:`crawler.run_batch`,
    ``width`` designs wide): each design's outputs, or its one-line error."""
    from bristlecrawler.crawler import run_batch
    from bristlecrawler.errors import SolverError
    from bristlecrawler.scenario.convert import to_spec
    from bristlecrawler.scenario.load import scenario_from_dict

    scs = [scenario_from_dict(s, "design") for s in scenarios]
    result = run_batch([to_spec(sc) for sc in scs], width=width)
    return [
        _fe_outputs(h, sc.actuation.cycles) if h is not None else one_line(SolverError(err))
        for h, err, sc in zip(result.histories, result.errors, scs, strict=True)
    ]


def _closed_form(s, fp, k, n) -> dict[str, np.ndarray]:
    """Two-bristle crawler, sin^2 stroke: the closed forms, vectorised over designs."""
    from bristlecrawler.reduced import closed_form as cf

    c = fp / k
    work = cf.work(s, fp, k, n)
    dissipation = cf.dissipation(s, fp, k, n)
    elastic = cf.final_elastic_energy(s, fp, k)
    scale = np.maximum.reduce([np.abs(work), dissipation, elastic])
    with np.errstate(divide="ignore", invalid="ignore"):
        balance = np.where(scale > 0, np.abs(work - elastic - dissipation) / scale, 0.0)
    metrics = DesignMetrics(
        net_advance=cf.net_advance(s, c, n),
        last_cycle_advance=np.where(n > 1, cf.net_advance_later(s, c), cf.net_advance_first(s, c)),
        cycles=n,
        work=work,
        mean_abs_connector_force=cf.mean_abs_force(s, fp, k, n),
        max_abs_connector_force=cf.peak_force(s, fp, k),
        energy_balance_rel_error=balance,
        steps=np.zeros(s.shape),
        newton_iterations=np.zeros(s.shape),
    )
    return metrics.to_dict()


def evaluate_reduced(config: dict[str, Any]) -> dict[str, float]:
    """One reduced design with the exact solver (any number of bristles, gait, stroke)."""
    from bristlecrawler.reduced.simulate import simulate
    from bristlecrawler.scenario.reduced import ReducedConfig, build
    from bristlecrawler.scenario.strict import parse_model

    cfg = parse_model(ReducedConfig, config)
    crawler, gait = build(cfg)
    r = simulate(crawler, gait, cfg.cycles, cfg.samples_per_cycle)
    return {k: float(v) for k, v in DesignMetrics.from_reduced(r, cfg.cycles).to_dict().items()}


def evaluate_reduced_chunk(
    base: dict[str, Any], values: dict[str, np.ndarray], solver: str = "auto"
) -> dict[str, np.ndarray]:
    """A chunk of reduced designs: ``base`` options with ``values`` (key -> array over the
    chunk's designs). Closed forms in bulk where they hold exactly (two bristles, sin^2
    stroke; with ``solver = 'auto'``), the exact solver design by design elsewhere.
    Returns every output, ``status`` and ``error`` (arrays over the chunk)."""
    n = len(next(iter(values.values())))

    def col(key: str) -> np.ndarray:
        if key in values:
            return np.asarray(values[key])
        return np.full(n, base[key], dtype=object if base[key] is None else None)

    res = {k: np.full(n, np.nan) for k in OUTPUTS}
    status = np.full(n, int(DesignStatus.DONE), np.int8)
    error = np.full(n, "", dtype=object)
    bulk = (
        (col("bristles") == 2)
        & (col("stroke") == "sin2")
        & (col("actuator") == "sin2")
        & (col("history") == None)  # noqa: E711 (elementwise)
        & (col("texture") == None)  # noqa: E711 (elementwise)
    )
    if solver != "auto":
        bulk[:] = False
    if bulk.any():
        t0 = time.perf_counter()
        args = (col(k)[bulk].astype(float) for k in ("s_max", "fp", "k", "cycles"))
        for k, v in _closed_form(*args).items():
            res[k][bulk] = v
        res["wall_time_s"][bulk] = (time.perf_counter() - t0) / bulk.sum()
    for i in np.flatnonzero(~bulk):
        t0 = time.perf_counter()
        try:
            row = base | {k: _python(np.asarray(v)[i]) for k, v in values.items()}
            for k, v in evaluate_reduced(row).items():
                res[k][i] = v
        except Exception as exc:  # a failed design is recorded, the others go on
            status[i], error[i] = DesignStatus.FAILED, one_line(exc)
        res["wall_time_s"][i] = time.perf_counter() - t0
    return res | {"status": status, "error": error.astype(str)}


def _python(value: Any) -> Any:
    """A numpy scalar as its Python value (an object array's items already are)."""
    return value.item() if isinstance(value, np.generic) else value


def one_line(exc: BaseException) -> str:
    """A failure as one line: its type and message, at most 500 characters."""
    text = " ".join(str(exc).split()) or type(exc).__name__
    return f"{type(exc).__name__}: {text}"[:500]
