"""xarray Datasets of results and their atomic NetCDF output (netCDF4 engine)."""

from __future__ import annotations

import os
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from bristlecrawler.io.atomic import atomic_path

if TYPE_CHECKING:  # pragma: no cover
    import xarray as xr

    from bristlecrawler.reduced.solver import ReducedResult


def write_netcdf(ds: xr.Dataset, path: str | os.PathLike) -> Path:
    """Write ``ds`` to ``path`` atomically (NetCDF4 format)."""
    with atomic_path(path, suffix=".nc") as tmp:
        ds.to_netcdf(tmp, engine="netcdf4")
    return Path(path)


def reduced_dataset(result: ReducedResult, attrs: dict[str, Any] | None = None) -> xr.Dataset:
    """The reduced-model time series as an xarray Dataset (units in each variable's attrs)."""
    import xarray as xr

    n = result.crawler.n_bristles
    laws = result.crawler.texture_laws()  # on a texture: its laws, and their means
    c = result.crawler.paper_crawler()
    ev = result.events
    ds = xr.Dataset(
        data_vars={
            "segment_shortening": (
                ("time", "segment"),
                result.shortening,
                {"units": "mm", "long_name": "segment shortening s_j(t)"},
            ),
            "s": (
                "time",
                result.shortening.sum(axis=1),
                {"units": "mm", "long_name": "body shortening (sum over segments)"},
            ),
            "delta": (
                "time",
                result.delta,
                {"units": "mm", "long_name": "front-end displacement Delta(t)"},
            ),
            "rear_displacement": (
                "time",
                result.rear_displacement,
                {"units": "mm", "long_name": "rear-end displacement"},
            ),
            "attachment_position": (
                ("time", "bristle"),
                result.X,
                {"units": "mm", "long_name": "bristle attachment position X_i"},
            ),
            "tip_position": (
                ("time", "bristle"),
                result.x,
                {"units": "mm", "long_name": "bristle tip position x_i (offset removed)"},
            ),
            "force": (
                ("time", "bristle"),
                result.force,
                {"units": "N", "long_name": "horizontal force F_i on the crawler"},
            ),
            "state": (
                ("time", "bristle"),
                result.state,
                {
                    "long_name": "stick/slip state over the preceding interval",
                    "flag_values": np.array([-1, 0, 1], dtype=np.int8),
                    "flag_meanings": "slip_backward stick slip_forward",
                },
            ),
            "elastic_energy": ("time", result.elastic_energy, {"units": "mJ"}),
            "dissipation": (
                "time",
                result.dissipation,
                {"units": "mJ", "long_name": "cumulative frictional dissipation"},
            ),
            "work": ("time", result.work, {"units": "mJ", "long_name": "cumulative actuator work"}),
            "energy_balance_residual": (
                "time",
                result.work - result.elastic_energy - result.dissipation,
                {"units": "mJ", "long_name": "W - E_el - D"},
            ),
            "k": ("bristle", c.k, {"units": "N/mm"}),
            "fp": ("bristle", c.fp, {"units": "N", "long_name": "F_p (along the grain)"}),
            "fn": ("bristle", c.fn, {"units": "N", "long_name": "F_n (against the grain)"}),
            "segment_length": ("segment", c.segment_lengths, {"units": "mm"}),
            "cycle_start_index": ("cycle_bound", result.cycle_bounds),
            "event_time": ("event", np.array([e.t for e in ev], dtype=float), {"units": "s"}),
            "event_bristle": ("event", np.array([e.bristle for e in ev], dtype=np.int32)),
            "event_state_before": ("event", np.array([e.before for e in ev], dtype=np.int8)),
            "event_state_after": ("event", np.array([e.after for e in ev], dtype=np.int8)),
        },
        coords={
            "time": ("time", result.t, {"units": "s"}),
            "bristle": np.arange(n),
            "segment": np.arange(n - 1),
        },
        attrs={"model": "bristlecrawler reduced 1-D model", "units": "mm, N, s, mJ"},
    )
    if laws is not None and len({law.n_cells for law in laws}) == 1:
        ds = ds.assign(
            texture_fp=(("bristle", "cell"), np.array([law.fp_N for law in laws]), {"units": "N"}),
            texture_fn=(("bristle", "cell"), np.array([law.fn_N for law in laws]), {"units": "N"}),
        )
        ds.attrs["texture_pitch_mm"] = laws[0].pitch_mm
        ds["fp"].attrs["long_name"] = "mean of F_p(x) over a pitch"
    if attrs:
        ds.attrs.update(
            {k: (v if isinstance(v, int | float | str) else str(v)) for k, v in attrs.items()}
        )
    return ds
