"""The ``bristlecrawler reduced`` job: solve, summarise, write NetCDF, figures and metadata."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

from bristlecrawler.reduced import closed_form as cf
from bristlecrawler.reduced.simulate import simulate
from bristlecrawler.reduced.solver import ReducedResult
from bristlecrawler.results import keys
from bristlecrawler.results.metrics import RunMetrics
from bristlecrawler.scenario.cost import MAX_REDUCED_S, reduced_run
from bristlecrawler.scenario.reduced import ReducedConfig, build

#: The exact solver closes the energy balance to round-off; a residual above this flags a
#: run whose events were not resolved.
BALANCE_WARN = 1e-6


@dataclass(frozen=True)
class ReducedRun:
    """A finished reduced-model run: the result, its summary and where files went."""

    result: ReducedResult
    summary: dict[str, Any]
    out_dir: Path | None
    notes: tuple[str, ...] = ()


def summarize(result: ReducedResult, config: ReducedConfig) -> dict[str, Any]:
    """Summary numbers (units in the key names)."""
    _, work = result.per_cycle()
    out: dict[str, Any] = RunMetrics.from_reduced(result).to_dict() | {
        keys.WORK_PER_CYCLE_MJ: work.tolist(),
        "dissipation_mJ": float(result.dissipation[-1]),
        "final_elastic_energy_mJ": float(result.elastic_energy[-1]),
        "energy_balance_rel_error": result.energy_balance_error,
        "bristles": result.crawler.n_bristles,
        "gait": config.gait,
        "model": "paper" if config.texture is None else "texture",
        "fp_over_k_mm": _fp_over_k(result.crawler, config),
        "samples": int(result.t.size),
        "events": len(result.events),
        "warnings": [],
    }
    if not result.energy_balance_error <= BALANCE_WARN:
        out["warnings"].append(
            f"energy balance residual {result.energy_balance_error:.1e} (normal: below "
            f"{BALANCE_WARN:g}): the event-driven solver lost track of a stick/slip event"
        )
    plain = config.history is None and config.actuator == "sin2" and config.texture is None
    if config.bristles == 2 and plain:
        out["regime"] = int(cf.regime(config.s_max, config.fp / config.k))
        out["closed_form_net_advance_mm"] = float(
            cf.net_advance(config.s_max, config.fp / config.k, config.cycles)
        )
        out["closed_form_work_mJ"] = float(
            cf.work(config.s_max, config.fp, config.k, config.cycles)
        )
    return out


def _fp_over_k(crawler, config: ReducedConfig) -> float:
    """F_p/k of the run, mm (a texture law's: its mean F_p over its k)."""
    laws = crawler.texture_laws()
    if laws is None:
        return float(config.fp / config.k)
    return float(laws[0].mean_fp_N / laws[0].k_N_per_mm)


def reduced_estimate(config: ReducedConfig):
    """The a-priori cost of ``config``'s run (:func:`bristlecrawler.scenario.cost.reduced_run`)."""
    return reduced_run(config.bristles, config.cycles, config.samples_per_cycle, config.gait)


def run_reduced(
    config: ReducedConfig,
    out: str | Path | None = None,
    write: bool = True,
    figures: bool = True,
    command: str = "",
    replace: bool = False,
) -> ReducedRun:
    """Solve; with ``write``, put ``reduced.nc``, figures, ``summary.json``, ``config.json``
    and ``meta.json`` in ``out`` (default ``runs/<timestamp>-reduced``).

    The folder is claimed before the solve and appears complete or not at all
    (:func:`bristlecrawler.io.runs.claim_run_dir`; ``replace`` replaces a run already there).
    """
    reduced_estimate(config).check(None, max_seconds=MAX_REDUCED_S)  # before any work
    crawler, gait = build(config)
    if not write:
        result = simulate(crawler, gait, config.cycles, config.samples_per_cycle)
        return ReducedRun(result, summarize(result, config), None)

    from bristlecrawler.io.jsonio import dumps_strict
    from bristlecrawler.io.netcdf import reduced_dataset, write_netcdf
    from bristlecrawler.io.runs import claim_run_dir

    with claim_run_dir(out, "reduced", replace=replace, command=command) as run:
        result = simulate(crawler, gait, config.cycles, config.samples_per_cycle)
        summary = summarize(result, config) | {"output_dir": str(run.target)}
        info = run.write_metadata(config.model_dump(), command)
        attrs = info.as_dict() | {"config": dumps_strict(config.model_dump())}
        write_netcdf(reduced_dataset(result, attrs=attrs), run.path / "reduced.nc")
        run.results_written("reduced.nc")
        if figures:
            from bristlecrawler.viz.reduced import plot_delta_vs_s, plot_friction_law, save_figure

            title = (
                f"reduced model: N={crawler.n_bristles}, {config.gait}, "
                f"F_p/k={summary['fp_over_k_mm']:.3g} mm, net {result.net_advance:.2f} mm"
            )
            save_figure(plot_delta_vs_s(result, title=title), run.path / "delta_vs_s.png")
            laws = crawler.texture_laws()
            if laws is None:
                law = plot_friction_law(crawler.paper_crawler().friction(0))
                save_figure(law, run.path / "friction_law.png")
            else:
                from bristlecrawler.viz.drag import plot_texture

                save_figure(plot_texture(laws[0]), run.path / "texture.png")
        run.write_json("summary.json", summary)
    return ReducedRun(result, summary, run.target, tuple(run.notes))
