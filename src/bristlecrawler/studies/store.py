"""The study folder: the resolved study, one part file per finished task, the gathered store.

```
OUT/study.json       the resolved study (base configuration included) and its fingerprint
OUT/meta.json        package version, git revision, command, start time
OUT/parts/*.npz      one per finished task, written atomically the moment it finishes
OUT/study.zarr       every design's outputs on the design axes (xarray / Zarr)
OUT/designs.csv      the same as a flat table (studies up to 100 000 designs)
OUT/figures/*.png
```

A part file is complete or absent (write, then rename), so a sweep killed at any instant
leaves only finished tasks behind; ``--resume`` skips them.
"""

from __future__ import annotations

import hashlib
import json
import os
import shutil
from pathlib import Path
from typing import Any

import numpy as np

from bristlecrawler.errors import InputError
from bristlecrawler.io.atomic import atomic_path, atomic_write_text
from bristlecrawler.studies.designs import Designs
from bristlecrawler.studies.evaluate import INTEGER_OUTPUTS, OUTPUTS, DesignStatus

STUDY_FILE, META_FILE, PARTS, STORE, TABLE = (
    "study.json",
    "meta.json",
    "parts",
    "study.zarr",
    "designs.csv",
)
CSV_LIMIT = 100_000


def fingerprint(resolved: dict[str, Any]) -> str:
    """Identity of a resolved study: equal for the same designs of the same model."""
    text = json.dumps(resolved, sort_keys=True, default=str, separators=(",", ":"))
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def check_folder(out: Path, resolved: dict[str, Any], resume: bool) -> bool:
    """InputError, before any work, if ``out`` cannot take this study: it holds another
    study, this one without ``--resume``, or something else. Returns whether it holds
    this study already (a resume)."""
    from bristlecrawler.io.runs import check_out_dir

    study_file = out / STUDY_FILE
    if not study_file.is_file():
        check_out_dir(out)
        if out.is_dir() and any(out.iterdir()):
            raise InputError(f"output folder {out} is not empty and holds no study")
        return False
    from bristlecrawler._files import MAX_SMALL_BYTES, read_bytes

    try:
        held = json.loads(read_bytes(study_file, MAX_SMALL_BYTES))
    except (OSError, ValueError) as exc:
        raise InputError(f"{study_file}: unreadable ({exc})") from None
    if not isinstance(held, dict):
        raise InputError(f"{study_file}: not a study's record (a JSON object)")
    if held.get("fingerprint") != resolved["fingerprint"]:
        raise InputError(
            f"output folder {out} holds another study's results "
            f"({held.get('study', {}).get('name', '?')!r}); give another --out"
        )
    if not resume:
        raise InputError(
            f"output folder {out} already holds this study; add --resume to complete it "
            "or give another --out"
        )
    return True


def start_folder(out: Path, resolved: dict[str, Any], meta: dict[str, Any]) -> None:
    (out / PARTS).mkdir(parents=True, exist_ok=True)
    if not (out / STUDY_FILE).exists():
        atomic_write_text(out / STUDY_FILE, json.dumps(resolved, indent=2, default=str) + "\n")
    atomic_write_text(out / META_FILE, json.dumps(meta, indent=2) + "\n")


def part_path(out: Path, task: int) -> Path:
    return out / PARTS / f"task-{task:07d}.npz"


def write_part(out: Path, task: int, index: np.ndarray, result: dict[str, np.ndarray]) -> None:
    """Write one task's designs atomically (``index``: their design numbers)."""
    arrays = {k: np.asarray(v) for k, v in result.items() if k != "error"}
    arrays["error"] = np.asarray(result["error"], dtype=str)
    with atomic_path(part_path(out, task)) as tmp, open(tmp, "wb") as f:
        np.savez(f, index=np.asarray(index, np.int64), **arrays)


def read_parts(out: Path):
    """Yield ``(task, arrays)`` of every part file."""
    for path in sorted((out / PARTS).glob("task-*.npz")):
        with np.load(path, allow_pickle=False) as z:
            yield int(path.stem.split("-")[1]), {k: z[k] for k in z.files}


def finished_tasks(out: Path) -> set[int]:
    """Tasks whose every design is done or failed (a lost design is tried again)."""
    return {
        task for task, part in read_parts(out) if not np.any(part["status"] == DesignStatus.LOST)
    }


def gather(out: Path, designs: Designs, attrs: dict[str, Any]):
    """Every design's outputs (NaN and status PENDING where none yet) as an xarray Dataset
    with the design axes as coordinates."""
    import xarray as xr

    n = designs.n
    data = {k: np.full(n, np.nan) for k in OUTPUTS}
    status = np.full(n, int(DesignStatus.PENDING), np.int8)
    error = np.full(n, "", dtype=object)
    for _task, part in read_parts(out):
        ix = part["index"]
        for k in OUTPUTS:
            data[k][ix] = part[k]
        status[ix] = part["status"]
        error[ix] = part["error"]
    dims = tuple(d for d, _ in designs.dims)
    shape = designs.shape
    variables = {}
    for k, (unit, text) in OUTPUTS.items():
        values = data[k].reshape(shape)
        if k in INTEGER_OUTPUTS:
            values = np.where(np.isnan(values), -1, values).astype(np.int64)
        variables[k] = (dims, values, {"units": unit, "long_name": text})
    names = " ".join(s.name.lower() for s in DesignStatus)
    codes = np.array([int(s) for s in DesignStatus], np.int8)
    variables["status"] = (
        dims,
        status.reshape(shape),
        {"flag_values": codes, "flag_meanings": names, "long_name": "design status"},
    )
    variables["error"] = (dims, error.reshape(shape), {"long_name": "error message"})
    coords = {k: (dim, v) for k, (dim, v) in designs.coords.items()}
    return xr.Dataset(variables, coords=coords, attrs=attrs)


def write_store(out: Path, ds) -> Path:
    """Write ``study.zarr`` (Zarr format 2, consolidated: readable by plain
    ``xr.open_zarr``) next to the old one, then swap: a reader never sees half a store."""
    target = out / STORE
    tmp = out / f".{STORE}.{os.getpid()}"
    if tmp.exists():
        shutil.rmtree(tmp)
    ds.to_zarr(tmp, mode="w", zarr_format=2, consolidated=True)
    old = out / f".{STORE}.old.{os.getpid()}"
    if target.exists():
        target.rename(old)
    tmp.rename(target)
    if old.exists():
        shutil.rmtree(old)
    if ds.status.size <= CSV_LIMIT:
        frame = ds.to_dataframe().reset_index()
        atomic_write_text(out / TABLE, frame.to_csv(index=False))
    return target
