"""Verification of the FE core and the frictional contact against closed forms
(``bristlecrawler verify``).

:func:`run_all` runs every case of :mod:`cases` (FE core) and of :mod:`contact_rows`
(contact: Coulomb oscillator, block on an incline, pressed-and-dragged bristle, bristle
dragged across grooves) and returns the table rows and the JSON document; the tests call
the same functions.
"""

from __future__ import annotations

from bristlecrawler.verification.cases import Row


def run_all(contact: bool = True) -> tuple[list[Row], dict]:
    """All cases: (rows, JSON document with FE-computed values); ``contact=False`` leaves
    out the contact cases."""
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
    contact_doc = {}
    if contact:
        from bristlecrawler.verification.contact_rows import contact_rows

        more, contact_doc = contact_rows()
        rows += more
    doc = {
        "cantilever_tip_load": runs,
        **bristle,
        "mesh_convergence": conv,
        **contact_doc,
        "cases": [
            {
                "case": r.case,
                "quantity": r.quantity,
                "reference": r.reference,
                "computed": r.computed,
                "error": r.error,
                "tol": r.tol,
                "passed": r.passed,
            }
            for r in rows
        ],
        "passed": all(r.passed for r in rows),
    }
    return rows, doc


__all__ = ["Row", "run_all"]
