"""The finite-element crawler history as an xarray Dataset (NetCDF), units in attributes.

The variables are the declared quantities (:data:`.quantities.QUANTITIES`) that the
history has, and no others. Dimensions: time (every recorded step), bristle, segment
(bristles - 1), xy, frame, node, line, end, substrate_point. xarray is imported when a
dataset is made.
"""

from __future__ import annotations

import warnings
from typing import Any

from bristlecrawler.crawler.quantities import QUANTITIES


def crawler_dataset(h, attrs: dict[str, Any] | None = None):
    """Dataset of the declared quantities of the history ``h``, the run's statistics and
    ``attrs`` in its attributes."""
    import xarray as xr

    _warn_undeclared(h)
    data, coords = {}, {}
    for q in QUANTITIES:
        value = q.value(h)
        if value is not None:
            (coords if q.coordinate else data)[q.name] = (q.dims, value, q.attrs())
    ds = xr.Dataset(
        data,
        coords=coords,
        attrs={
            "model": "bristlecrawler finite-element crawler",
            "units": "mm, N, s, t, mJ",
            "name": h.name,
        },
    )
    ds.attrs.update(_run_attrs(h, attrs))
    return ds


def _warn_undeclared(h) -> None:
    """A series the history holds that no declaration names is left out of the file:
    it would have no unit and no description."""
    declared = {q.home for q in QUANTITIES} | {q.name for q in QUANTITIES}
    extra = [f"energies.{k}" for k in h.energies if f"energies.{k}" not in declared]
    extra += [k for k in h.quantities if k not in declared]
    if extra:
        warnings.warn(
            f"left out of the dataset: {', '.join(extra)} (not declared in "
            "bristlecrawler.crawler.quantities.QUANTITIES)",
            stacklevel=3,
        )


def _run_attrs(h, attrs: dict[str, Any] | None) -> dict:
    """The run's statistics, the caller's attributes (strings where not numbers), the
    period and the number of cycles."""
    extra = dict(h.stats) | (attrs or {})
    out = {k: v if isinstance(v, int | float | str) else str(v) for k, v in extra.items()}
    if h.period is not None:
        out["period_s"] = float(h.period)
    out["cycles"] = int(h.cycles)
    return out
