"""Verification of the FE core against closed forms (``bristlecrawler verify``).

:func:`run_all` runs every case of :mod:`cases` and returns the table rows and the JSON
document; the tests call the same functions.
"""

from __future__ import annotations

from bristlecrawler.verification.cases import Row


def run_all() -> tuple[list[Row], dict]:
    """All cases: (rows, JSON document with FE-computed values)."""
    from bristlecrawler.verification import cases

    runs = cases.tip_load_runs()
    rows = cases.case_tip_load(runs)
    rows += cases.case_end_moment()
    bristle_rows, bristle = cases.case_bristle()
    rows += bristle_rows
    rows += cases.case_tip_mass_frequency()
    rows += cases.case_energy()
    rows += cases.case_hht()
    conv = cases.convergence()
    rows += cases.case_convergence(conv)
    doc = {
        "cantilever_tip_load": runs,
        **bristle,
        "mesh_convergence": conv,
        "cases": [
            {"case": r.case, "quantity": r.quantity, "reference": r.reference,
             "computed": r.computed, "error": r.error, "tol": r.tol, "passed": r.passed}
            for r in rows
        ],
        "passed": all(r.passed for r in rows),
    }
    return rows, doc


__all__ = ["Row", "run_all"]
