"""Convergence study of the FE crawler: element size and time-step tolerance.

Runs a shipped scenario (default ``paper``) at its own resolution and at the refinements
the issue asks for: twice the elements per bristle (half the element size), a tenth of
``dt_max`` and of the step energy tolerance, a bound on the energy a step may lose (a
tenth of it when there is one), a tenth of the stick drift (the friction penalty), and
Newton without its trust region (``solver.max_correction = inf``, when it has one).
Prints one row per run and the change of the net advance (mm) and of the connector work
(%) against the base run; nothing is asserted.

    python bench/convergence_crawler.py [--scenario paper] [--cycles 1]
                                        [--set section.key=value ...]

Each row is a full simulation (one 20 s cycle of the paper scenario: 1 to 5 minutes on
the 2-core machine), so this is a study, not a test.
"""

from __future__ import annotations

import argparse
import math

from _crawler_rows import run_rows


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scenario", default="paper")
    ap.add_argument("--cycles", type=int, default=1)
    ap.add_argument("--set", dest="sets", action="append", default=[])
    a = ap.parse_args()

    from bristlecrawler.fe import enable_compilation_cache
    from bristlecrawler.scenario.load import apply_overrides, load_scenario

    enable_compilation_cache()
    base = apply_overrides(load_scenario(a.scenario), [*a.sets, f"actuation.cycles={a.cycles}"])
    n, dt, tol = base.bristle.elements, base.solver.dt_max, base.solver.energy_tol
    loss, drift = base.solver.energy_loss_tol, base.contact.stick_drift
    # Without a loss bound the snaps' loss is not controlled: bound it by energy_tol.
    loss_to = loss / 10 if math.isfinite(loss) else tol
    variants = [
        ("base", []),
        (f"elements {2 * n}", [f"bristle.elements={2 * n}"]),
        (f"dt_max {dt / 10:g}", [f"solver.dt_max={dt / 10!r}"]),
        (f"energy_tol {tol / 10:g}", [f"solver.energy_tol={tol / 10!r}"]),
        (f"energy_loss {loss_to:g}", [f"solver.energy_loss_tol={loss_to!r}"]),
        (f"stick_drift {drift / 10:g}", [f"contact.stick_drift={drift / 10!r}"]),
    ]
    if math.isfinite(base.solver.max_correction):
        variants.append(("max_correction inf", ["solver.max_correction=inf"]))
    print(
        f"scenario {base.name}, {a.cycles} cycle(s): {n} elements per bristle, "
        f"dt_max {dt:g} s, energy_tol {tol:g} mJ, energy_loss_tol {loss:g} mJ, "
        f"stick_drift {drift:g} mm"
    )
    run_rows(base, variants)


if __name__ == "__main__":
    main()
