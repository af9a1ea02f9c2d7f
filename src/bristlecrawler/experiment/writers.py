"""Writing recordings as CSV or TDMS (atomically), e.g. synthetic test data."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from bristlecrawler.experiment.readers import ChannelMap
from bristlecrawler.experiment.recording import Recording
from bristlecrawler.io.atomic import atomic_path


def _columns(rec: Recording, cmap: ChannelMap) -> dict[str, np.ndarray]:
    cols = {
        cmap.time or "time_s": rec.t,
        cmap.left: cmap.left_sign * rec.left,
        cmap.right: cmap.right_sign * rec.right,
    }
    for role in ("current", "shortening", "force"):
        values = getattr(rec, role)
        if values is not None and getattr(cmap, role):
            cols[getattr(cmap, role)] = values
    return cols


def write_csv(rec: Recording, path: str | os.PathLike, cmap: ChannelMap | None = None) -> Path:
    """CSV with a header; NaN samples are written as empty cells, as loggers do."""
    cols = _columns(rec, cmap or ChannelMap())
    data = np.column_stack(list(cols.values()))
    with atomic_path(path) as tmp, open(tmp, "w", encoding="utf-8") as fh:
        fh.write(",".join(cols) + "\n")
        for row in data:
            fh.write(",".join("" if not np.isfinite(v) else f"{v:.6g}" for v in row) + "\n")
    return Path(path)


def write_tdms(
    rec: Recording, path: str | os.PathLike, cmap: ChannelMap | None = None, group: str = "crawler"
) -> Path:
    """TDMS with one group; each channel carries ``unit_string`` and ``wf_increment``."""
    from nptdms import ChannelObject, GroupObject, TdmsWriter

    cmap = cmap or ChannelMap()
    cols = _columns(rec, cmap)
    units = {
        cmap.time or "time_s": "s",
        cmap.left: "mm",
        cmap.right: "mm",
        cmap.current: "A",
        cmap.shortening: "mm",
        cmap.force: "N",
    }
    dt = float(np.median(np.diff(rec.t)))
    objects = [GroupObject(group, properties={"source": "bristlecrawler"})]
    for name, values in cols.items():
        props = {"unit_string": units.get(name, ""), "wf_increment": dt, "wf_start_offset": 0.0}
        objects.append(ChannelObject(group, name, np.asarray(values, float), properties=props))
    with atomic_path(path, suffix=".tdms") as tmp:
        with TdmsWriter(str(tmp)) as writer:
            writer.write_segment(objects)
    return Path(path)
