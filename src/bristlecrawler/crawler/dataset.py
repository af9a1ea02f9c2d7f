"""The finite-element crawler history as an xarray Dataset (NetCDF), units in attributes.

Dimensions: time (every recorded step), bristle, segment (bristles - 1), xy, frame, node,
line, substrate_point. xarray is imported when a dataset is made.
"""

from __future__ import annotations

from typing import Any

import numpy as np

_ENERGY_NAMES = {
    "elastic": "elastic energy of the bristles and contact penalties, from the first record",
    "kinetic": "kinetic energy, from the first record",
    "potential": "gravitational potential energy, from the first record",
    "friction": "energy dissipated by friction",
    "damping": "energy dissipated by Rayleigh damping",
    "external": "external work (the connector's, W_c)",
}


def crawler_dataset(h, attrs: dict[str, Any] | None = None):
    """Dataset with dims time, bristle, xy, frame, node, line."""
    import xarray as xr

    resid = h.energy_balance_residual()
    data = {
        # + 0.0: a shortening of -0.0 (the first record) is written as 0.0
        "s": (
            "time",
            h.s + 0.0,
            {"units": "mm", "long_name": "shortening s (of the first segment)"},
        ),
        "delta": ("time", h.delta, {"units": "mm", "long_name": "right-end displacement Delta"}),
        "left": (
            ("time", "xy"),
            h.left,
            {"units": "mm", "long_name": "left end (first body node)"},
        ),
        "right": (
            ("time", "xy"),
            h.right,
            {"units": "mm", "long_name": "right end (last body node)"},
        ),
        "connector_force": (
            "time",
            h.connector_force,
            {"units": "N", "long_name": "connector force F_c of the first segment (pulling)"},
        ),
        "connector_work": (
            "time",
            h.connector_work,
            {"units": "mJ", "long_name": "connector work W_c = sum over segments of int F_c ds"},
        ),
        "tip_position": (
            ("time", "bristle", "xy"),
            h.tip_position,
            {"units": "mm", "long_name": "bristle tip position (bristles from the left)"},
        ),
        "tip_state": (
            ("time", "bristle"),
            h.tip_state.astype(np.int8),
            {
                "flag_values": np.array([0, 1, 2], np.int8),
                "flag_meanings": "open stick slip",
                "long_name": "contact state of the bristle tip",
            },
        ),
        "energy_balance_residual": (
            "time",
            resid - resid[0],
            {
                "units": "mJ",
                "long_name": "energy balance residual: W_c minus stored energies and dissipations",
            },
        ),
    }
    data |= _drawing(h) | _optional(h)
    for name, series in h.energies.items():
        what = _ENERGY_NAMES.get(name, f"{name} energy")
        data[f"energy_{name}"] = ("time", series, {"units": "mJ", "long_name": what})
    ds = xr.Dataset(
        data,
        coords={
            "time": ("time", h.t, {"units": "s"}),
            "frame_time": ("frame", h.frame_t, {"units": "s"}),
            "xy": ["x", "y"],
        },
        attrs={
            "model": "bristlecrawler finite-element crawler",
            "units": "mm, N, s, t, mJ",
            "name": h.name,
        },
    )
    ds.attrs.update(_run_attrs(h, attrs))
    return ds


def _optional(h) -> dict:
    """The variables of a history that has per-segment records and section thicknesses."""
    out = {}
    if h.segment_shortening is not None:
        out["segment_shortening"] = (
            ("time", "segment"),
            h.segment_shortening + 0.0,
            {"units": "mm", "long_name": "shortening of each body segment"},
        )
        out["segment_force"] = (
            ("time", "segment"),
            h.segment_force,
            {"units": "N", "long_name": "connector force of each segment's actuator (pulling)"},
        )
    if h.node_thickness is not None:
        out["node_thickness"] = (
            "node",
            h.node_thickness,
            {"units": "mm", "long_name": "bristle section thickness at the node (0 elsewhere)"},
        )
    return out


def _drawing(h) -> dict:
    """The variables that draw the crawler: frames, line cells and the substrate."""
    return {
        "frame_nodes": (
            ("frame", "node", "xy"),
            h.frame_nodes,
            {"units": "mm", "long_name": "node positions of the drawn frames"},
        ),
        "lines": (
            ("line", "end"),
            h.lines.astype(np.int32),
            {"long_name": "nodes of the drawing's line cells"},
        ),
        "line_kind": (
            "line",
            h.line_kind.astype(np.int8),
            {
                "flag_values": np.array([0, 1, 2], np.int8),
                "flag_meanings": "body link bristle",
                "long_name": "kind of line cell",
            },
        ),
        "substrate_xy": (
            ("substrate_point", "xy"),
            h.substrate_xy,
            {"units": "mm", "long_name": "substrate surface (drawing, fillets left out)"},
        ),
    }


def _run_attrs(h, attrs: dict[str, Any] | None) -> dict:
    """The run's statistics, the caller's attributes (strings where not numbers), the
    period and the number of cycles."""
    extra = dict(h.stats) | (attrs or {})
    out = {k: v if isinstance(v, int | float | str) else str(v) for k, v in extra.items()}
    if h.period is not None:
        out["period_s"] = float(h.period)
    out["cycles"] = int(h.cycles)
    return out
