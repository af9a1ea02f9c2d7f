"""xarray Datasets of results and their atomic NetCDF output (netCDF4 engine)."""

from __future__ import annotations

import os
from pathlib import Path
from typing import TYPE_CHECKING, Any, NamedTuple

import numpy as np

from bristlecrawler.io.atomic import atomic_path
from bristlecrawler.results.variables import Variable, variables_markdown

if TYPE_CHECKING:  # pragma: no cover
    import xarray as xr

    from bristlecrawler.reduced.solver import ReducedResult


def write_netcdf(ds: xr.Dataset, path: str | os.PathLike) -> Path:
    """Write ``ds`` to ``path`` atomically (NetCDF4 format)."""
    with atomic_path(path, suffix=".nc") as tmp:
        ds.to_netcdf(tmp, engine="netcdf4")
    return Path(path)


class _Reduced(NamedTuple):
    """What ``reduced.nc`` is made of: the run, its crawler's paper-model view (k, F_p,
    F_n, segment lengths; on a texture its laws' means), the laws on a texture (or None)
    and the stick/slip events."""

    result: Any
    crawler: Any
    laws: Any
    events: Any


def _on_texture(src: _Reduced) -> bool:
    return src.laws is not None and len({law.n_cells for law in src.laws}) == 1


#: The variables of ``reduced.nc``, in the file's order.
REDUCED_VARIABLES: tuple[Variable, ...] = (
    Variable(
        "segment_shortening",
        ("time", "segment"),
        "mm",
        "shortening s_j(t) of each segment",
        lambda r: r.result.shortening,
    ),
    Variable(
        "s",
        ("time",),
        "mm",
        "body shortening (sum over segments)",
        lambda r: r.result.shortening.sum(axis=1),
    ),
    Variable("delta", ("time",), "mm", "front-end displacement Delta(t)", lambda r: r.result.delta),
    Variable(
        "rear_displacement",
        ("time",),
        "mm",
        "rear-end displacement",
        lambda r: r.result.rear_displacement,
    ),
    Variable(
        "attachment_position",
        ("time", "bristle"),
        "mm",
        "bristle attachment position X_i",
        lambda r: r.result.X,
    ),
    Variable(
        "tip_position",
        ("time", "bristle"),
        "mm",
        "bristle tip position x_i (offset removed)",
        lambda r: r.result.x,
    ),
    Variable(
        "force",
        ("time", "bristle"),
        "N",
        "horizontal force F_i of each bristle on the crawler",
        lambda r: r.result.force,
    ),
    Variable(
        "state",
        ("time", "bristle"),
        "",
        "stick/slip state over the preceding interval",
        lambda r: r.result.state,
        flags=((-1, "slip_backward"), (0, "stick"), (1, "slip_forward")),
    ),
    Variable(
        "elastic_energy",
        ("time",),
        "mJ",
        "elastic energy of the bristles",
        lambda r: r.result.elastic_energy,
    ),
    Variable(
        "dissipation",
        ("time",),
        "mJ",
        "cumulative frictional dissipation",
        lambda r: r.result.dissipation,
    ),
    Variable("work", ("time",), "mJ", "cumulative actuator work", lambda r: r.result.work),
    Variable(
        "energy_balance_residual",
        ("time",),
        "mJ",
        "W - E_el - D (round-off)",
        lambda r: r.result.work - r.result.elastic_energy - r.result.dissipation,
    ),
    Variable(
        "k",
        ("bristle",),
        "N/mm",
        "bristle stiffness k (on a texture: its law's)",
        lambda r: r.crawler.k,
    ),
    Variable(
        "fp",
        ("bristle",),
        "N",
        "F_p, resistance along the grain (on a texture: the mean of F_p(x) over a pitch)",
        lambda r: r.crawler.fp,
    ),
    Variable(
        "fn",
        ("bristle",),
        "N",
        "F_n, resistance against the grain (on a texture: the mean of F_n(x) over a pitch)",
        lambda r: r.crawler.fn,
    ),
    Variable(
        "segment_length",
        ("segment",),
        "mm",
        "rest length of each segment",
        lambda r: r.crawler.segment_lengths,
    ),
    Variable(
        "cycle_start_index",
        ("cycle_bound",),
        "",
        "sample index at which each cycle starts (and the last sample)",
        lambda r: r.result.cycle_bounds,
    ),
    Variable(
        "event_time",
        ("event",),
        "s",
        "time of each stick/slip change",
        lambda r: np.array([e.t for e in r.events], dtype=float),
    ),
    Variable(
        "event_bristle",
        ("event",),
        "",
        "the bristle that changed state",
        lambda r: np.array([e.bristle for e in r.events], dtype=np.int32),
    ),
    Variable(
        "event_state_before",
        ("event",),
        "",
        "its state before (the codes of `state`)",
        lambda r: np.array([e.before for e in r.events], dtype=np.int8),
    ),
    Variable(
        "event_state_after",
        ("event",),
        "",
        "its state after (the codes of `state`)",
        lambda r: np.array([e.after for e in r.events], dtype=np.int8),
    ),
    Variable(
        "texture_fp",
        ("bristle", "cell"),
        "N",
        "on a texture: each bristle's resistance along the grain in each cell of the pitch",
        lambda r: np.array([law.fp_N for law in r.laws]),
        when=_on_texture,
    ),
    Variable(
        "texture_fn",
        ("bristle", "cell"),
        "N",
        "on a texture: each bristle's resistance against the grain in each cell of the "
        "pitch (inf at a wall)",
        lambda r: np.array([law.fn_N for law in r.laws]),
        when=_on_texture,
    ),
)


def reduced_variables_markdown() -> str:
    """The reference table of ``reduced.nc``'s variables."""
    return variables_markdown(REDUCED_VARIABLES)


def reduced_dataset(result: ReducedResult, attrs: dict[str, Any] | None = None) -> xr.Dataset:
    """The reduced-model time series as an xarray Dataset, its variables those of
    :data:`REDUCED_VARIABLES` (units and meaning in each variable's attrs)."""
    import xarray as xr

    n = result.crawler.n_bristles
    laws = result.crawler.texture_laws()  # on a texture: its laws, and their means
    src = _Reduced(result, result.crawler.paper_crawler(), laws, result.events)
    ds = xr.Dataset(
        data_vars={
            v.name: v.variable(src) for v in REDUCED_VARIABLES if v.when is None or v.when(src)
        },
        coords={
            "time": ("time", result.t, {"units": "s"}),
            "bristle": np.arange(n),
            "segment": np.arange(n - 1),
        },
        attrs={"model": "bristlecrawler reduced 1-D model", "units": "mm, N, s, mJ"},
    )
    if _on_texture(src):
        ds.attrs["texture_pitch_mm"] = laws[0].pitch_mm
    if attrs:
        ds.attrs.update(
            {k: (v if isinstance(v, int | float | str) else str(v)) for k, v in attrs.items()}
        )
    return ds
