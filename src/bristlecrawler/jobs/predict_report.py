"""What a prediction says of itself: which model made each number, what that model
assumed, where a model does not apply to the design, and which model to believe where the
two disagree.

The reduced models take the drag test's numbers as they come. Where the test found the
bristle resisting backwards no more than forwards (F_n < F_p: directional friction reversed
or absent), the paper's model, whose law needs F_n >= F_p, is not applicable: it is not
run, and the prediction says so, as ``bristlecrawler reduced`` refuses such numbers.
"""

from __future__ import annotations

import math
from typing import Any

from bristlecrawler.results import keys

#: Where the reduced models were compared with the FE crawler (the docs' comparison tables).
FINDINGS = "docs/findings.md, 'The texture model against the FE crawler'"
#: Where the bristled model was compared with the FE crawler.
BRISTLED_FINDINGS = "docs/findings.md, 'The bristled model against the FE crawler'"

#: The model whose numbers a prediction gives first.
DEFAULT = "bristled"

#: Model name -> how the output names it, the default first.
LABELS = {
    DEFAULT: "bristled model (elastic rods on the grooves, no FE)",
    "texture": "texture-law model",
    "paper": "paper's model (k, F_p, F_n)",
}

#: Model name -> where it was checked against the FE crawler, in one line.
CHECKED = {
    DEFAULT: (
        f"{BRISTLED_FINDINGS}: on two-bristle designs at 45 degrees the steady cycle equal "
        "to the FE's and the work within 0.9 % (7 designs, pitch 1.5 to 4 mm); at 30 "
        "degrees the work 22-35 % high; with three or more bristles it does not settle "
        "(no result)"
    ),
    "texture": f"{FINDINGS}: steady cycle within half a pitch on 2 of 7 designs",
    "paper": f"{FINDINGS}: steady cycle within half a pitch on 1 of 7 designs",
}


def bristled_assumptions(spec, cycles: int) -> str:
    """What the bristled model assumed, in one line."""
    return (
        f"{len(spec.bristles)} bristles at the design's places, its breathing stroke, "
        f"{cycles} cycles; each bristle a two-joint elastic rod with the tapered beam's "
        "tip stiffness, its last quarter's outline on the real grooves (held at the angle "
        "the weight gives it), Coulomb friction at the tip only, the body rigid and in "
        "equilibrium under its weight; quasi-static"
    )


def paper_model_refusal(fp: float, fn: float, scatter: float = math.nan) -> str | None:
    """Why the paper's model cannot take a drag test's F_p, F_n (N), or None where it can.
    ``scatter``: the pitch-to-pitch standard deviation of F_p, N (NaN: not known)."""
    if not (math.isfinite(fp) and math.isfinite(fn)) or fn >= fp:
        return None
    within = ""
    if math.isfinite(scatter) and scatter > 0:
        side = "within" if fp - fn <= scatter else "beyond"
        within = f", {fp - fn:.3f} N apart: {side} F_p's scatter of {scatter:.3f} N"
    return (
        f"the drag test found F_n = {fn:.3f} N < F_p = {fp:.3f} N{within}: the bristle "
        "resists backwards no more than forwards (directional friction reversed or absent "
        "on this design); the paper's model needs F_n >= F_p, so it was not run"
    )


def assumptions(summary, cycles: int, bristles: int) -> dict[str, str]:
    """What each model assumed, in one line each (``summary``: the drag test's
    :class:`~bristlecrawler.results.drag.DragSummary`)."""
    law = summary.texture
    where = f"{bristles} bristles at the design's places, its stroke, {cycles} cycles"
    walls = ", walls that lock a tip" if len(law.walls_mm) else ""
    return {
        "texture": (
            f"{where}; each tip resists as the drag test's texture law says where it is in "
            f"the {law.pitch_mm:g} mm pitch ({law.n_cells} cells of F_p(x), F_n(x){walls}), "
            f"k = {summary.k:.3f} N/mm"
        ),
        "paper": (
            f"{where}; one F_p = {summary.fp:.3f} N and F_n = {summary.fn:.3f} N for every "
            f"place on the substrate (the drag test's means over whole pitches: no "
            f"grooves), k = {summary.k:.3f} N/mm"
        ),
    }


def disagreement(
    texture: dict[str, Any], paper: dict[str, Any] | None, pitch_mm: float, bristles: int
) -> str | None:
    """The line for two models that differ by more than a pitch per cycle (their
    ``RunMetrics`` mappings), or None: which one the FE crawler has checked on designs like
    this one, and where the comparison is."""
    if paper is None:
        return None
    per = [len(texture[keys.ADVANCE_PER_CYCLE_MM]), len(paper[keys.ADVANCE_PER_CYCLE_MM])]
    cycles = max(min(per), 1)
    gap = abs(texture[keys.NET_ADVANCE_MM] - paper[keys.NET_ADVANCE_MM]) / cycles
    if not gap > pitch_mm:
        return None
    head = f"the two models differ by {gap:.2f} mm per cycle, more than the {pitch_mm:g} mm pitch."
    if bristles == 2:
        body = (
            " Checked against the FE crawler on two-bristle designs, the texture-law model "
            "came closer: it advances by whole pitches where the FE crawler does, and at 45 "
            "degrees its work was within 5 % of the FE's on 7 of 8 designs (the paper's "
            "model: 2 to 19 % low); neither model's advance was within half a pitch of the "
            "FE's on most designs."
        )
    else:
        body = (
            f" On designs of {bristles} bristles neither model has matched the FE crawler "
            "(on three bristles the texture-law model stays put where the FE crawler "
            "advances): run `bristlecrawler simulate` on this design before trusting either."
        )
    return f"{head}{body} See {FINDINGS}."
