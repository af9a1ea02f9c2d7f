"""ParaView output: a time series of line meshes (.vtu per frame, indexed by a .pvd file).

The crawler's beams, links and body are polylines; each frame is an unstructured grid of
line cells written with meshio, and ``series.pvd`` lists the frames with their times so
ParaView plays them as one animation.
"""

from __future__ import annotations

import os
from pathlib import Path
from xml.sax.saxutils import quoteattr

import numpy as np

from bristlecrawler.errors import InputError
from bristlecrawler.io.atomic import atomic_path, atomic_write_text


def write_vtk_series(
    folder: str | os.PathLike,
    times: np.ndarray,
    points: np.ndarray,
    lines: np.ndarray,
    point_data: dict[str, np.ndarray] | None = None,
    cell_data: dict[str, np.ndarray] | None = None,
    name: str = "crawler",
) -> Path:
    """Write ``<name>_NNNN.vtu`` per frame and ``<name>.pvd``; returns the .pvd path.

    Args:
        times: frame times, s, shape (F,).
        points: node coordinates, mm, shape (F, P, 2) or (F, P, 3).
        lines: line-cell connectivity (two point indices per cell), shape (C, 2).
        point_data: per-node fields, each (F, P) or (F, P, k).
        cell_data: per-cell fields, each (F, C) or (F, C, k).
    """
    import meshio

    times = np.asarray(times, float)
    pts = np.asarray(points, float)
    if pts.ndim != 3 or pts.shape[0] != times.size or pts.shape[2] not in (2, 3):
        raise InputError(f"points must have shape ({times.size}, P, 2|3), got {pts.shape}")
    lines = np.asarray(lines, dtype=np.int64)
    if lines.ndim != 2 or lines.shape[1] != 2 or lines.min() < 0 or lines.max() >= pts.shape[1]:
        raise InputError("lines must be (C, 2) indices into the points")
    if pts.shape[2] == 2:
        pts = np.concatenate([pts, np.zeros((*pts.shape[:2], 1))], axis=2)
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    entries = []
    for f, t in enumerate(times):
        mesh = meshio.Mesh(
            pts[f],
            [("line", lines)],
            point_data={k: np.asarray(v)[f] for k, v in (point_data or {}).items()},
            cell_data={k: [np.asarray(v)[f]] for k, v in (cell_data or {}).items()},
        )
        fname = f"{name}_{f:05d}.vtu"
        with atomic_path(folder / fname, suffix=".vtu") as tmp:
            meshio.write(tmp, mesh, file_format="vtu")
        entries.append(f'    <DataSet timestep="{t:.9g}" part="0" file={quoteattr(fname)}/>')
    pvd = (
        '<?xml version="1.0"?>\n'
        '<VTKFile type="Collection" version="0.1" byte_order="LittleEndian">\n'
        "  <Collection>\n" + "\n".join(entries) + "\n  </Collection>\n</VTKFile>\n"
    )
    return atomic_write_text(folder / f"{name}.pvd", pvd)
