"""Is the crawler quasi-static? The FE model under the SMA history against the sin^2 stroke.

Paper Section 2 drives the prototype with a closed-loop SMA actuator (current on until
s reaches s~, off until the crawler is back to its length, about 20 s a cycle); its
Sections 3-4 model the stroke as s~ sin^2(pi t / T). The reduced model is rate-independent,
so both give the same Delta(s) (``examples/sma_actuated_gait.py``). The FE model has
inertia and damping, so here the two histories are compared on it: Delta at the stroke's
turning points (full contraction, end of the cycle) and the Delta(s) curves.

Two runs of ``bristlecrawler simulate`` (one cycle each; both together took 2 min 38 s
on a 2-core machine, compilation included), or their existing output folders:

    python examples/quasi_static_fe.py                       # runs both (writes runs/)
    python examples/quasi_static_fe.py --runs SIN2_DIR SMA_DIR --out fig.png
"""

from __future__ import annotations

import argparse
import datetime
from pathlib import Path

import numpy as np


def turning_points(ds) -> dict[str, float]:
    """Delta (mm) at the largest shortening and at the end of the run, the largest
    shortening (mm), and the energy-balance residual relative to the work (the trust flag)."""
    s = ds["s"].values
    delta = ds["delta"].values
    i = int(np.argmax(s))
    res = ds["energy_balance_residual"].values
    work = float(np.max(np.abs(ds["connector_work"].values)))
    return {
        "s_peak_mm": float(s[i]),
        "delta_at_peak_mm": float(delta[i]),
        "delta_end_mm": float(delta[-1]),
        "balance_rel": float(np.max(np.abs(res - res[0])) / max(work, 1e-300)),
    }


def run_pair(out_root: Path) -> tuple[Path, Path]:
    """Run the paper scenario for one cycle with each actuator; returns the two folders."""
    from bristlecrawler.fe import enable_compilation_cache
    from bristlecrawler.jobs.simulate import run_simulation
    from bristlecrawler.scenario.load import apply_overrides, load_scenario

    enable_compilation_cache()
    folders = []
    for kind in ("sin2", "sma"):
        sc = apply_overrides(
            load_scenario("paper"),
            [
                "actuation.cycles=1",
                f'actuation.kind="{kind}"',
                "output.vtk=false",
                "output.animation=false",
            ],
        )
        # A fresh folder per run: a folder that holds a run is refused.
        stamp = datetime.datetime.now(datetime.UTC).strftime("%Y%m%d-%H%M%S")
        out = out_root / f"{stamp}-quasi-static-{kind}"
        run_simulation(sc, out=out, progress=True, command=f"examples/quasi_static_fe.py {kind}")
        folders.append(out)
    return folders[0], folders[1]


def compare(sin2_dir: Path, sma_dir: Path, figure: Path | None = None) -> dict:
    """Turning-point table of the two runs, and the Delta(s) overlay written to ``figure``."""
    import xarray as xr

    rows = {}
    curves = {}
    for name, folder in (("sin2", sin2_dir), ("sma", sma_dir)):
        with xr.open_dataset(Path(folder) / "crawler.nc") as ds:
            rows[name] = turning_points(ds)
            curves[name] = (ds["s"].values.copy(), ds["delta"].values.copy())
    if figure is not None:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        fig, ax = plt.subplots(figsize=(6, 4))
        for name, style in (("sin2", "-"), ("sma", "--")):
            s, d = curves[name]
            ax.plot(s, d, style, label=f"{name}: Delta end {rows[name]['delta_end_mm']:.2f} mm")
        ax.set_xlabel("shortening s (mm)")
        ax.set_ylabel("Delta (mm)")
        ax.set_title("FE crawler, one cycle: SMA history vs sin^2 stroke")
        ax.legend()
        fig.tight_layout()
        Path(figure).parent.mkdir(parents=True, exist_ok=True)
        fig.savefig(figure, dpi=120)
        plt.close(fig)
    return rows


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", nargs=2, type=Path, metavar=("SIN2_DIR", "SMA_DIR"))
    ap.add_argument("--out", type=Path, default=Path("runs") / "quasi_static_fe.png")
    a = ap.parse_args()
    for folder in a.runs or ():
        if not (folder / "crawler.nc").is_file():
            why = "no crawler.nc (not a `bristlecrawler simulate` run folder)"
            ap.exit(2, f"error: {folder}: {why}\n")
    sin2_dir, sma_dir = a.runs if a.runs else run_pair(Path("runs"))
    rows = compare(sin2_dir, sma_dir, a.out)
    print(f"{'history':>8} {'s peak':>8} {'Delta peak':>11} {'Delta end':>10} {'balance':>8}")
    for name, r in rows.items():
        print(
            f"{name:>8} {r['s_peak_mm']:>8.3f} {r['delta_at_peak_mm']:>11.3f} "
            f"{r['delta_end_mm']:>10.3f} {100 * r['balance_rel']:>7.1f}%"
        )
    print(f"figure: {a.out}")


if __name__ == "__main__":
    main()
