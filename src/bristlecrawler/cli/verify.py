"""``bristlecrawler verify``: FE core against closed forms (see bristlecrawler.verification)."""

from __future__ import annotations

from typing import Annotated

import typer


def verify_cmd(
    as_json: Annotated[
        bool, typer.Option("--json", help="print one JSON object on stdout and nothing else")
    ] = False,
) -> None:
    """Run the FE and contact verification cases; print a table; exit 1 if any fails.

    FE core: tip-loaded elastica (P L^2/EI = 1, 2, 5, 10), end moment rolling up a full
    circle, tapered bristle tip and horizontal stiffness, tip-mass cantilever frequency,
    trapezoidal-rule energy, HHT dissipation, mesh convergence order. Contact: Coulomb
    oscillator (turning points, stop time, dissipation), block on an incline pushed
    horizontally, pressed-and-dragged bristle (stick then slip), bristle tip dragged
    across grooves (energy balance).
    """
    from bristlecrawler.fe import enable_compilation_cache
    from bristlecrawler.io.jsonio import dumps_strict

    enable_compilation_cache()
    from bristlecrawler.verification import run_all

    rows, doc = run_all()
    if as_json:
        typer.echo(dumps_strict(doc))
    else:
        from rich.console import Console
        from rich.table import Table

        table = Table(title="bristlecrawler verification (FE core and contact)")
        for col in ("case", "quantity", "reference", "computed", "rel. error", "tol", "pass"):
            table.add_column(col, justify="left" if col in ("case", "quantity") else "right")
        for r in rows:
            table.add_row(
                r.case,
                r.quantity,
                f"{r.reference:.10g}",
                f"{r.computed:.10g}",
                f"{r.error:.2e}",
                f"{r.tol:.0e}",
                "yes" if r.passed else "NO",
            )
        console = Console(width=140)
        console.print(table)
        conv = doc["mesh_convergence"]
        orders = ", ".join(f"{p:.3f}" for p in conv["orders"])
        console.print(f"mesh convergence, n = {conv['sizes']}: observed orders {orders}")
        console.print(
            f"paper bristle (alpha = pi/4): horizontal stiffness "
            f"{doc['bristle_horizontal_stiffness_N_per_mm']:.4f} N/mm "
            "(reduced model of the paper: k = 0.48 N/mm)"
        )
        if "grooved_drag" in doc:
            g = doc["grooved_drag"]
            e = ", ".join(f"{k} {v:.4f}" for k, v in g["energies_mJ"].items())
            console.print(
                f"grooved drag, energies at the end (mJ): {e}; peak normal force "
                f"{g['peak_normal_force_N']:.3f} N"
            )
    if not doc["passed"]:
        raise typer.Exit(1)


def register(app: typer.Typer) -> None:
    app.command("verify")(verify_cmd)
