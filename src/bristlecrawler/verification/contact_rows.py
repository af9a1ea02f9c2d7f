"""Rows of ``bristlecrawler verify`` for the frictional-contact cases.

Each function takes a finished run (or runs the case) and returns ``(rows, doc)``: the
table rows (:class:`~bristlecrawler.verification.cases.Row`: case, quantity, reference,
computed, error, tolerance) and the values of the ``--json`` document. The tolerances are
the error budgets stated in each docstring, not fits to the observed errors.
"""

from __future__ import annotations

import functools
import math
from typing import NamedTuple

import numpy as np

from bristlecrawler.verification.cases import Row, row


def coulomb_oscillator_rows(run=None) -> tuple[list[Row], dict]:
    """Turning points, stop time and dissipated energy of the FE Coulomb oscillator (HHT,
    dt = 1 ms) against the closed form.

    Budgets (dt = 1 ms, stick drift delta = 1e-4 mm, four reversals before the stop):
    a reversal falls inside a step, and the friction force flips at the step's end; in the
    penalty's stick zone (2 delta wide) it turns gradually. Both shift the phase, by up to
    2 mu g dt / |a| and sqrt(4 delta / |a|) per reversal (|a| the acceleration after it,
    7057 down to 1171 mm/s^2): 2.8e-3 of the stop time in all, tolerance 3e-3. Positions
    move only at second order, (2 mu g dt)^2 / (2 |a|) + 2 delta per reversal: 4e-5 of x0
    in all, tolerance 1e-4 of x0. The energy dissipated by the return mapping against the
    spring energy lost between release and the closed form's rest position: tolerance 1e-4
    (the end position error and the stick spring's energy are below 1e-6).
    """
    from bristlecrawler.verification.contact_cases import coulomb_oscillator_fe

    run = coulomb_oscillator_fe() if run is None else run
    ref = run.reference
    case = "Coulomb oscillator"
    x0 = abs(float(ref.positions[0]))
    n_ref, n_fe = len(ref.positions), len(run.turning_points)
    rows = [row(case, "turning points (release + reversals + stop)", n_ref, n_fe, 0.0)]
    for k in range(1, min(n_ref, n_fe)):
        rows.append(
            row(
                case,
                f"turning point {k} (mm), error / x0",
                ref.positions[k],
                run.turning_points[k],
                1e-4,
                scale=x0,
            )
        )
    rows.append(row(case, "stop time (s)", ref.stop_time, run.stop_time, 3e-3))
    stiffness = 0.1  # N/mm, DEFAULT_OSCILLATOR
    loss = 0.5 * stiffness * (ref.positions[0] ** 2 - ref.positions[-1] ** 2)
    rows.append(
        row(case, "friction dissipation (mJ) vs spring energy lost", loss, run.dissipation, 1e-4)
    )
    doc = {
        "coulomb_oscillator_turning_points_mm": [float(x) for x in run.turning_points[:6]],
        "coulomb_oscillator_turning_times_s": [float(t) for t in run.turning_times[:6]],
        "coulomb_oscillator_stop_time_s": float(run.stop_time),
        "coulomb_oscillator_dissipation_mJ": float(run.dissipation),
    }
    return rows, doc


def incline_rows(run=None) -> tuple[list[Row], dict]:
    """Push/weight at the onset of sliding up the incline (tan a = 0.1, mu = 0.3) against
    (tan a + mu) / (1 - mu tan a). Budget: the onset is solved exactly for contact forces
    affine in the push (quasi-static stick); what is left is the driving spring's turn,
    (block travel) / (spring length) < 1e-5 rad, and the inertia of the slow loading:
    tolerance 1e-4."""
    from bristlecrawler.verification.contact_cases import incline_push_fe

    run = incline_push_fe() if run is None else run
    rows = [row("block on incline", "push / weight at slip onset", run.reference, run.ratio, 1e-4)]
    return rows, {"incline_push_ratio": float(run.ratio)}


def pressed_drag_rows(run=None) -> tuple[list[Row], dict]:
    """The paper's bristle at pi/6, pressed 5 micrometres on a flat plane and dragged (tip
    trailing), against the linearised stick-then-slip answer. FE values at a press of 5 and
    2.5 micrometres extrapolated to zero press (the geometrically nonlinear FE deviates at
    first order in the press). Budget: the penalty compliance (penetration and stick drift
    1e-4 of the press, amplified up to about 3 times by the ratio of compliances) and
    second-order terms in the press (1e-5): tolerance 1e-3."""
    from bristlecrawler.verification.contact_beam_cases import pressed_beam_drag_fe

    run = pressed_beam_drag_fe() if run is None else run
    ref = run.reference
    case = "pressed-dragged bristle"
    rows = [
        row(case, "clamp drag at slip onset (mm)", ref.drag_at_slip, run.drag_at_slip, 1e-3),
        row(case, "normal force after press (N)", ref.normal_at_press, run.normal_at_press, 1e-3),
        row(case, "normal force in slip (N)", ref.normal_in_slip, run.normal_in_slip, 1e-3),
    ]
    doc = {
        "pressed_bristle_drag": {
            "drag_at_slip_mm": run.drag_at_slip,
            "normal_at_press_N": run.normal_at_press,
            "normal_in_slip_N": run.normal_in_slip,
            "raw": [dict(r) for r in run.raw],
        }
    }
    return rows, doc


def _bound_row(case, quantity, bound, computed) -> Row:
    """A row that passes when ``computed`` <= ``bound``; error = relative excess."""
    excess = max(0.0, computed - bound) / bound if math.isfinite(computed) else math.inf
    return Row(case, quantity, float(bound), float(computed), float(excess), 0.0)


def grooved_drag_rows(run=None) -> tuple[list[Row], dict]:
    """The paper's bristle tip dragged across two of the paper's grooves (0.1 mm fillets).

    Energy balance: max over the run of |work in - (elastic + kinetic + friction +
    damping)| / max work in, tolerance 1e-3. The tip must drop into
    every groove it passes and climb out of it (counts against the grooves its path
    spans, exact), and the contact force stays finite: the penetration stays below the
    penalty's design value of 1e-4 mm (at 1 N).
    """
    from bristlecrawler.verification.contact_beam_cases import grooved_drag_fe

    run = grooved_drag_fe() if run is None else run
    case = "grooved drag"
    rows = [
        row(
            case,
            "energy balance, max |W_in - sum E| / max W_in",
            0.0,
            run.balance_rel_error,
            1e-3,
            scale=1.0,
        ),
        row(
            case,
            "grooves entered (of grooves passed)",
            run.grooves_passed,
            run.grooves_entered,
            0.0,
            scale=max(run.grooves_passed, 1),
        ),
        row(
            case,
            "grooves climbed out of (of grooves passed)",
            run.grooves_passed,
            run.climbs,
            0.0,
            scale=max(run.grooves_passed, 1),
        ),
        _bound_row(case, "peak penetration (mm), bound", 1e-4, run.max_penetration),
    ]
    E = run.energies
    doc = {
        "grooved_drag": {
            "energy_balance_rel_error": run.balance_rel_error,
            "energies_mJ": {k: float(v[-1]) for k, v in E.items()},
            "grooves_passed": run.grooves_passed,
            "grooves_entered": run.grooves_entered,
            "grooves_climbed": run.climbs,
            "peak_normal_force_N": float(np.max(run.p_n)),
            "peak_friction_force_N": float(np.max(np.abs(run.f_t))),
            "max_penetration_mm": run.max_penetration,
            "steps": int(len(run.t) - 1),
            "rejected_steps": run.rejected_steps,
        }
    }
    return rows, doc


class ContactRuns(NamedTuple):
    """The four contact cases at their defaults."""

    oscillator: object
    incline: object
    pressed: object
    grooved: object


@functools.lru_cache(maxsize=1)
def default_runs() -> ContactRuns:
    """Run the four contact cases once per process (``verify`` and the tests share them)."""
    from bristlecrawler.verification import contact_beam_cases as beam
    from bristlecrawler.verification import contact_cases as block

    return ContactRuns(
        block.coulomb_oscillator_fe(),
        block.incline_push_fe(),
        beam.pressed_beam_drag_fe(),
        beam.grooved_drag_fe(),
    )


def contact_rows(runs: ContactRuns | None = None) -> tuple[list[Row], dict]:
    """All contact cases: (rows, JSON values)."""
    runs = default_runs() if runs is None else runs
    rows, doc = [], {}
    for fn, run in (
        (coulomb_oscillator_rows, runs.oscillator),
        (incline_rows, runs.incline),
        (pressed_drag_rows, runs.pressed),
        (grooved_drag_rows, runs.grooved),
    ):
        r, d = fn(run)
        rows += r
        doc.update(d)
    return rows, doc


__all__ = [
    "ContactRuns",
    "contact_rows",
    "coulomb_oscillator_rows",
    "default_runs",
    "grooved_drag_rows",
    "incline_rows",
    "pressed_drag_rows",
]
