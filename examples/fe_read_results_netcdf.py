"""Read a finite-element run's results with xarray, as written to ``crawler.nc``.

``bristlecrawler simulate`` writes ``runs/<id>/crawler.nc``; give its path to read a run
of your own::

    python examples/fe_read_results_netcdf.py runs/<id>/crawler.nc

Without one, the example makes a short run (the inclined one of ``fe_run_scenario.py``),
writes its ``crawler.nc`` into a temporary folder and reads that. Every variable carries its
unit in ``attrs["units"]``; the docs' output reference lists them all.
"""

from __future__ import annotations

import sys
import tempfile
from pathlib import Path

import numpy as np
import xarray as xr

QUICK = [
    "actuation.s_max=8.0",  # mm
    "actuation.period=4.0",  # s
    "actuation.cycles=1",
]


def quick_run_file(folder: Path) -> Path:
    """A short run of ``paper`` written as ``folder/crawler.nc``."""
    from bristlecrawler.crawler import run
    from bristlecrawler.fe import enable_compilation_cache
    from bristlecrawler.io.netcdf import write_netcdf
    from bristlecrawler.scenario import load_spec

    enable_compilation_cache()
    history = run(load_spec("paper", QUICK))
    return write_netcdf(history.to_dataset(), folder / "crawler.nc")


def read(path: Path) -> dict[str, float]:
    """A few numbers from a ``crawler.nc``: units from the file's attributes."""
    with xr.open_dataset(path) as ds:
        assert ds["delta"].attrs["units"] == "mm" and ds["connector_work"].attrs["units"] == "mJ"
        i_peak = int(np.argmax(ds["s"].values))
        states = ds["tip_state"].values  # 0 open, 1 stick, 2 slip (flag_meanings)
        return {
            "net_advance_mm": float(ds["delta"][-1] - ds["delta"][0]),
            "delta_at_peak_shortening_mm": float(ds["delta"][i_peak]),
            "peak_shortening_mm": float(ds["s"][i_peak]),
            "connector_work_mJ": float(ds["connector_work"][-1]),
            "max_abs_connector_force_N": float(np.abs(ds["connector_force"]).max()),
            "right_tip_slip_fraction": float(np.mean(states[:, 1] == 2)),
            "energy_balance_residual_mJ": float(ds["energy_balance_residual"][-1]),
            "frames": int(ds.sizes["frame"]),
        }


if len(sys.argv) > 1 and __name__ == "__main__":
    numbers = read(Path(sys.argv[1]))
else:
    with tempfile.TemporaryDirectory() as tmp:
        numbers = read(quick_run_file(Path(tmp)))


def main() -> None:
    for key, value in numbers.items():
        print(f"{key:30s} {value:.6g}")


if __name__ == "__main__":
    main()
