"""Drag-test parameters (k, F_p, F_n) of the paper's bristle as its design and texture change.

One parameter at a time around the paper's design (alpha = 45 deg, grooves 2 mm pitch and
0.25 mm deep, mu = 0.65, tip 0.5 mm thick): the inclination from 0 to 75 degrees, the
groove pitch and depth, the friction coefficient and the tip thickness. Each design is one
drag test back and forth (two legs of 10 mm at 2 mm/s). Beside the drag k, the closed-form
horizontal stiffness of the tapered bristle (linear beam theory, without and with shear)::

    python examples/drag_parameter_study.py --out drag-study      # table, CSV and figure

About 18 drag tests: 30-60 minutes on a 2-core machine. ``--only alpha_deg`` runs one study;
``--only elements phase fillet_top penalty_load`` the study of what the drag test's k
depends on besides the bristle (the mesh, where the tip starts within a pitch, the land
edges' radius, the contact penalty).
"""

from __future__ import annotations

import argparse
import csv
import dataclasses
import math
import pathlib

from bristlecrawler.crawler import CrawlerSpec
from bristlecrawler.crawler.drag import DragTest, drag_test
from bristlecrawler.errors import SolverError
from bristlecrawler.fe import enable_compilation_cache
from bristlecrawler.verification.references import inclined_horizontal_stiffness

DRAG = DragTest(direction="cycle", distance=10.0, speed=2.0)
PAPER = CrawlerSpec.paper()


def _grooves(name):
    def change(v):
        return lambda s: dataclasses.replace(
            s, substrate=dataclasses.replace(s.substrate, **{name: v})
        )

    return change


def _bristles(name):
    return lambda v: lambda s: s.replace_bristles(**{name: v})


def _alpha(v):
    def change(s):
        s = s.replace_bristles(alpha_deg=v)
        if v > 65:  # a bristle this inclined lays more of its face below the lands' top
            c = dataclasses.replace(s.contact, active_points=max(s.contact.active_points, 48))
            s = dataclasses.replace(s, contact=c)
        return s

    return change


def _contact(name):
    def change(v):
        return lambda s: dataclasses.replace(s, contact=dataclasses.replace(s.contact, **{name: v}))

    return change


def _elements(v):
    return lambda s: s.replace_bristles(elements=int(v))


#: study -> (unit, values, value -> (spec -> spec))
STUDIES = {
    "alpha_deg": ("deg", (0, 15, 30, 45, 60, 75), _alpha),
    "pitch": ("mm", (1.5, 2.0, 3.0), _grooves("pitch")),
    "depth": ("mm", (0.1, 0.25, 0.5), _grooves("depth")),
    "mu": ("-", (0.3, 0.65, 1.0), _contact("mu")),
    "thickness_tip": ("mm", (0.25, 0.5, 1.0), _bristles("thickness_tip")),
    # What the bristle's k depends on besides the bristle: the mesh, where its tip starts
    # within a pitch (the grooves shifted under it), the land edges' radius and the
    # contact penalty (the load at which penetration stays below 1e-3 mm).
    "elements": ("-", (10, 20, 40, 80), _elements),
    "phase": ("mm", (0.0, 0.5, 1.0, 1.5), _grooves("phase")),
    "fillet_top": ("mm", (0.01, 0.02, 0.05), _grooves("fillet_top")),
    "penalty_load": ("N", (0.1, 0.3, 1.0, 3.0), _contact("penalty_load")),
}


def beam_stiffness(spec: CrawlerSpec, shear: bool) -> float:
    """Closed-form horizontal tip stiffness of the design's first bristle, N/mm."""
    b = spec.bristles[0]
    nu = b.poisson_ratio if shear else None
    args = (b.youngs_modulus, b.width, b.thickness_clamp, b.thickness_tip, b.length, b.alpha)
    return inclined_horizontal_stiffness(*args, nu=nu)


KEYS = (
    "k_N_per_mm",
    "k_initial_N_per_mm",
    "k_unload_N_per_mm",
    "k_texture_N_per_mm",
    "k_beam_N_per_mm",
    "k_beam_shear_N_per_mm",
    "fp_N",
    "fp_scatter_N",
    "fn_N",
    "fn_scatter_N",
    "mu_load_N",
    "fp_over_k_mm",
    "dissipation_mJ_per_mm",
    "energy_balance_rel_error",
)


def row(study: str, value: float, drag: DragTest = DRAG) -> dict:
    """One design of a study: its drag-test summary and the beam-theory stiffnesses."""
    spec = STUDIES[study][2](value)(PAPER)
    head = {"study": study, "value": value}
    try:
        s = drag_test(spec, drag).summary()
    except SolverError as exc:  # one design that fails does not end the study
        return head | {k: math.nan for k in KEYS} | {"failure": str(exc)}
    return head | {
        "k_N_per_mm": s["k_N_per_mm"],
        "k_initial_N_per_mm": s["k_initial_N_per_mm"],
        "k_unload_N_per_mm": s["k_unload_N_per_mm"],
        # the slope pooled over every phase in which the tip sticks: the texture law's k
        "k_texture_N_per_mm": s["texture"]["k_N_per_mm"] if s.get("texture") else math.nan,
        "k_beam_N_per_mm": beam_stiffness(spec, shear=False),
        "k_beam_shear_N_per_mm": beam_stiffness(spec, shear=True),
        "fp_N": s["fp_N"],
        "fp_scatter_N": s["fp_scatter_N"],
        "fn_N": s["fn_N"],
        "fn_scatter_N": s["fn_scatter_N"],
        "mu_load_N": s["mu_load_N"],
        "fp_over_k_mm": s["fp_over_k_mm"],
        "dissipation_mJ_per_mm": s["dissipation_mJ_per_mm"],
        "energy_balance_rel_error": s["energy_balance_rel_error"],
        "failure": "",
    }


def figure(rows: list[dict], path: pathlib.Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    studies = list(dict.fromkeys(r["study"] for r in rows))
    fig, axes = plt.subplots(2, len(studies), figsize=(3.2 * len(studies), 5.6), squeeze=False)
    for j, name in enumerate(studies):
        rs = [r for r in rows if r["study"] == name]
        v = [r["value"] for r in rs]
        top, bottom = axes[0, j], axes[1, j]
        top.errorbar(v, [r["fp_N"] for r in rs], [r["fp_scatter_N"] for r in rs], fmt="o-",
                     label="F_p (along)")  # fmt: skip
        top.errorbar(v, [r["fn_N"] for r in rs], [r["fn_scatter_N"] for r in rs], fmt="s-",
                     label="F_n (against)")  # fmt: skip
        top.plot(v, [r["mu_load_N"] for r in rs], "k:", label="mu W")
        bottom.plot(v, [r["k_N_per_mm"] for r in rs], "o-", label="drag test")
        bottom.plot(v, [r["k_beam_N_per_mm"] for r in rs], "--", label="beam")
        bottom.plot(v, [r["k_beam_shear_N_per_mm"] for r in rs], ":", label="beam + shear")
        bottom.set_xlabel(f"{name} ({STUDIES[name][0]})")
        if j == 0:
            top.set_ylabel("sliding force (N)")
            bottom.set_ylabel("k (N/mm)")
            top.legend(fontsize=7)
            bottom.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=120)


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--only", nargs="+", choices=sorted(STUDIES), default=list(STUDIES))
    ap.add_argument("--values", type=float, nargs="+", help="these values of the one study")
    ap.add_argument("--out", type=pathlib.Path, help="folder for drag-study.csv and .png")
    args = ap.parse_args(argv)
    enable_compilation_cache()
    keys = (
        "k_N_per_mm",
        "k_initial_N_per_mm",
        "k_texture_N_per_mm",
        "k_beam_N_per_mm",
        "k_beam_shear_N_per_mm",
        "fp_N",
        "fn_N",
        "mu_load_N",
    )
    print("| study | value | " + " | ".join(keys) + " |")
    print("|---" * (len(keys) + 2) + "|")
    rows = []
    for study in args.only:
        for value in args.values or STUDIES[study][1]:
            r = row(study, value)
            rows.append(r)
            vals = " | ".join(f"{r[k]:.3f}" if math.isfinite(r[k]) else "-" for k in keys)
            note = f" failed: {r['failure'][:160]}" if r["failure"] else ""
            print(f"| {study} | {value:g} | {vals} |{note}", flush=True)
    if args.out:
        args.out.mkdir(parents=True, exist_ok=True)
        with open(args.out / "drag-study.csv", "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=list(rows[0]))
            w.writeheader()
            w.writerows(rows)
        figure(rows, args.out / "drag-study.png")


if __name__ == "__main__":
    main()
