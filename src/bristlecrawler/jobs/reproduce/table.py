"""The table "paper versus bristlecrawler": each of the paper's numbers beside ours.

Every row names the paper's value (with where the paper gives it), ours (from which part
of the run), their difference, a verdict (agrees within the row's tolerance, differs, or
inconclusive where the data cannot tell) and the reason, with the section of the
documentation that explains it. The reasons quote docs/findings.md and docs/validation.md
(a test keeps the quotes in sync), so the report is complete without the docs.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import asdict, dataclass

from bristlecrawler.jobs.reproduce.parts import Context
from bristlecrawler.results import keys

FINDINGS = "findings.md"
VALIDATION = "validation.md"
PITCH = f"{FINDINGS}#the-gait-is-quantised-by-the-textures-pitch"
WORK = f"{FINDINGS}#the-connector-work-is-59-of-the-papers-and-why"
DRAG = f"{FINDINGS}#a-drag-test-of-the-papers-bristle-and-what-the-reduced-models-k-means"
VERTICAL = f"{FINDINGS}#alpha-0-paper-vertical-no-systematic-advance-a-random-walk-of-whole-pitches"
#: The documentation section behind each link, as the report names it.
SECTIONS = {
    PITCH: "Findings, \u201cThe gait is quantised by the texture's pitch\u201d",
    WORK: "Findings, \u201cThe connector work is 59 % of the paper's, and why\u201d",
    DRAG: "Findings, \u201cA drag test of the paper's bristle, and what the reduced model's "
    "k means\u201d",
    VERTICAL: "Findings, \u201calpha = 0 (paper-vertical): no systematic advance, a random "
    "walk of whole pitches\u201d",
    VALIDATION: "Validation, \u201cThe paper's numbers\u201d",
}

#: Quotes of the documentation, one per documented difference (whitespace normalised).
WHY_ADVANCE = (
    "The holding tip rests in a groove, so every steady cycle advances a whole number of "
    "groove pitches"
)
WHY_WORK = (
    "None of the inputs the paper leaves open moves the work by more than 13 %; the "
    "damping's reference frequency moves it to 62.4 mJ; the paper's F_p = 0.45 N exceeds "
    "what a tip sliding on a land can resist, which points at a contact definition the "
    "paper does not state"
)
WHY_FORCE = (
    "The paper's F_p = 0.45 N exceeds mu times the *whole* weight (0.351 N), which no tip "
    "sliding on a land can give quasi-statically."
)
WHY_DRAG = (
    "A reduced k fitted to a crawler on grooves is therefore an *effective* k that lumps "
    "the backslip of a texture-quantised gait into an elastic lag; it describes that "
    "crawler on that texture and stroke, not the bristle."
)
WHY_CALIBRATED = (
    "calibrated on our FE run: F_p/k is fixed by the advance and the work scales with F_p, "
    "so F_p and k both follow our FE work, which is below the paper's (see the work row)"
)
BY_CONSTRUCTION = (
    "agrees by construction: the synthetic recording is made with the reduced model at "
    "F_p = 0.456 N and k = 0.48 N/mm, so this row checks the analysis, not the paper"
)
WHY_VERTICAL = (
    "a single five-cycle run is a sum of whole-pitch steps whose sign is decided by "
    "round-off, so it meets |net| < 2 mm by chance or misses it"
)
#: Which page each quote is from (the test reads them there).
QUOTED = {
    WHY_ADVANCE: FINDINGS,
    WHY_WORK: VALIDATION,
    WHY_FORCE: FINDINGS,
    WHY_DRAG: FINDINGS,
    WHY_VERTICAL: VALIDATION,
}


@dataclass(frozen=True)
class Row:
    """One line of the table (values in ``unit``; None where not available)."""

    key: str
    quantity: str
    unit: str
    paper: float | None
    paper_text: str
    ours: float | None
    ours_text: str
    source: str
    agrees: bool | None  #: True agrees, False differs, None inconclusive or not compared
    reason: str
    link: str  #: the documentation page and section, relative to docs/ ("" if none)
    verdict: str = "n/a"  #: agrees, differs, inconclusive or n/a (not compared)
    docs: str = ""  #: the documentation section, by name

    @property
    def difference(self) -> float | None:
        if self.paper is None or self.ours is None:
            return None
        return self.ours - self.paper

    def as_dict(self) -> dict:
        return asdict(self) | {"difference": self.difference}


@dataclass(frozen=True)
class RowSpec:
    """How to fill a row: where our value comes from and when it agrees.

    ``get(ctx) -> (value, text, source)`` gives ours (value None: not available, text says
    why); ``tol`` is the largest |ours - paper| that agrees; ``why`` and ``link`` explain a
    disagreement; ``judge(ctx, spec) -> (verdict, reason)`` replaces the comparison with
    the tolerance where a row needs another rule (None: not judged, the comparison)."""

    key: str
    quantity: str
    unit: str
    paper: float | None
    paper_text: str
    get: Callable[[Context], tuple[float | None, str, str]]
    tol: float
    why: str
    link: str
    judge: Callable[[Context, RowSpec], tuple[str, str] | None] | None = None


def _fe(key: str, scale: Callable[[float, int], float] = lambda v, n: v, five: bool = False):
    """Our value from the alpha = pi/4 FE run; ``five``: only comparable over five cycles."""

    def get(ctx: Context):
        v, n = ctx.value("fe-paper", key), ctx.value("fe-paper", "cycles")
        if v is None:
            return None, _missing(ctx, "fe-paper"), "FE, alpha = pi/4"
        if five and n != 5:
            return None, f"{v:.3f} over {n} cycle(s) (--quick)", f"FE, alpha = pi/4, {n} cycles"
        return scale(v, n), "", f"FE, alpha = pi/4, {n} cycles"

    return get


def _missing(ctx: Context, part: str, otherwise: str = "not available") -> str:
    """Why a part's number is missing: the part failed, did not run, or gave none."""
    r = ctx.results.get(part)
    if r is None:
        return f"{part} not run"
    return f"{part} failed" if not r.ok else otherwise


def _mean_cycle(ctx: Context):
    v = ctx.value("fe-paper", keys.ADVANCE_PER_CYCLE_MM)
    n = ctx.value("fe-paper", "cycles")
    if v is None:
        return None, _missing(ctx, "fe-paper"), "FE, alpha = pi/4"
    return sum(v) / len(v), "", f"FE, alpha = pi/4, mean of {n} cycle(s)"


def _calibrated(key: str):
    def get(ctx: Context):
        cal = ctx.value("reduced", "fe_calibration")
        if not cal or key not in cal:
            return None, "no FE calibration", "reduced model calibrated on our FE run"
        return cal[key], "", f"calibrated on our FE run ({cal['cycles']} cycles)"

    return get


def _drag(key: str):
    def get(ctx: Context):
        v = ctx.value("drag", key)
        if v is None:
            return None, _missing(ctx, "drag", "gave none"), "drag test of the FE bristle"
        return v, "", "drag test of the FE bristle"

    return get


def _recording(ctx: Context):
    v = ctx.value("experiment", "fp_over_k_mm")
    src = ctx.value("experiment", "source")
    if v is None:
        return None, "no estimate", "recording"
    return v, "", f"{'synthetic' if src == 'synthetic' else 'given'} recording, fitted"


def _recording_advance(ctx: Context):
    v, n = ctx.value("experiment", keys.NET_ADVANCE_MM), ctx.value("experiment", "cycles")
    if v is None:
        return None, "no analysis", "recording"
    if n != 5:
        return None, f"{v:.2f} over {n} cycles", "recording"
    return v, "", "recording, five cycles"


def _synthetic(ctx: Context, spec: RowSpec) -> tuple[str, str] | None:
    """The rows of the synthetic recording agree by construction (when they agree)."""
    if ctx.value("experiment", "source") != "synthetic":
        return None
    v = spec.get(ctx)[0]
    if v is None or not abs(v - spec.paper) <= spec.tol:
        return None
    return "agrees", BY_CONSTRUCTION


def _no_advance(ctx: Context, spec: RowSpec) -> tuple[str, str] | None:
    """The verdict of :func:`no_advance_verdict` on the cycles of the starting places."""
    from bristlecrawler.jobs.reproduce.verdict import no_advance_verdict

    cycles = ctx.value("fe-vertical", keys.ADVANCE_PER_CYCLE_MM)
    if not cycles:
        return None
    v = no_advance_verdict(cycles, spec.tol, spec.unit)
    reason = v.reason
    if v.verdict != "agrees":
        reason += ". " + WHY_VERTICAL[:1].upper() + WHY_VERTICAL[1:]
    return v.verdict, reason


def _vertical(ctx: Context):
    mean = ctx.value("fe-vertical", "advance_per_cycle_mean_mm")
    sem = ctx.value("fe-vertical", "advance_per_cycle_sem_mm")
    places = ctx.value("fe-vertical", "starting_places_mm")
    if mean is None:
        return None, _missing(ctx, "fe-vertical"), "FE, alpha = 0"
    if sem is None:
        text = f"{mean:+.2f} (one starting place: no standard error)"
    else:
        text = f"{mean:+.2f} ± {sem:.2f} (standard error)"
    n = len(places)
    return mean, text, f"FE, alpha = 0, one cycle from {n} starting place{'s' * (n > 1)}"


ROWS: tuple[RowSpec, ...] = (
    RowSpec(
        keys.NET_ADVANCE_MM,
        "net advance over five cycles (FE)",
        "mm",
        82.0,
        "82 ± 4",
        _fe(keys.NET_ADVANCE_MM, five=True),
        4.0,
        WHY_ADVANCE,
        PITCH,
    ),
    RowSpec(
        keys.ADVANCE_PER_CYCLE_MM,
        "advance per cycle (FE)",
        "mm",
        16.4,
        "82 / 5",
        _mean_cycle,
        0.8,
        WHY_ADVANCE,
        PITCH,
    ),
    RowSpec(
        keys.WORK_MJ,
        "work over five cycles (FE)",
        "mJ",
        75.0,
        "about 75",
        _fe(keys.WORK_MJ, five=True),
        7.5,
        WHY_WORK,
        WORK,
    ),
    RowSpec(
        "mean_connector_force_N",
        "mean connector force |F_c| (FE)",
        "N",
        0.45,
        "0.45 (= F_p)",
        _fe("mean_abs_connector_force_N"),
        0.045,
        WHY_FORCE,
        WORK,
    ),
    RowSpec(
        "fp_over_k_mm",
        "F_p/k",
        "mm",
        0.95,
        "0.95",
        _calibrated("fp_over_k_mm"),
        0.05,
        WHY_ADVANCE,
        PITCH,
    ),
    RowSpec(
        keys.FP_N, "F_p", "N", 0.45, "0.45", _calibrated(keys.FP_N), 0.045, WHY_CALIBRATED, WORK
    ),
    RowSpec(
        keys.K_N_PER_MM,
        "k",
        "N/mm",
        0.48,
        "0.48",
        _calibrated(keys.K_N_PER_MM),
        0.048,
        WHY_CALIBRATED,
        WORK,
    ),
    RowSpec(
        "fp_drag_N", "F_p (drag test)", "N", 0.45, "0.45", _drag(keys.FP_N), 0.045, WHY_DRAG, DRAG
    ),
    RowSpec(
        "k_drag_N_per_mm",
        "k (drag test)",
        "N/mm",
        0.48,
        "0.48",
        _drag(keys.K_N_PER_MM),
        0.048,
        WHY_DRAG,
        DRAG,
    ),
    RowSpec(
        "fp_over_k_recording_mm",
        "F_p/k (experiment analysis)",
        "mm",
        0.95,
        "0.95",
        _recording,
        0.05,
        "",
        VALIDATION,
        _synthetic,
    ),
    RowSpec(
        "net_advance_recording_mm",
        "net advance over five cycles (experiment)",
        "mm",
        82.0,
        "about 82 ± 1",
        _recording_advance,
        1.0,
        "",
        VALIDATION,
        _synthetic,
    ),
    RowSpec(
        "advance_alpha0_mm_per_cycle",
        "advance per cycle at alpha = 0 (FE)",
        "mm",
        0.0,
        "no appreciable net advancement",
        _vertical,
        2.0,
        WHY_VERTICAL,
        VERTICAL,
        _no_advance,
    ),
)


def _judged(ctx: Context, spec: RowSpec, ours: float | None, text: str) -> tuple[str, str]:
    """(verdict, reason) of a row: its own rule, else the comparison with the tolerance."""
    if ours is None or spec.paper is None or not math.isfinite(ours):
        return "n/a", "not compared: " + (text or "no value")
    own = spec.judge(ctx, spec) if spec.judge is not None else None
    if own is not None:
        return own
    if abs(ours - spec.paper) <= spec.tol:
        return "agrees", f"agrees within {spec.tol:g} {spec.unit}"
    return "differs", spec.why or "see the validation page"


def build_table(ctx: Context) -> list[Row]:
    """The rows, filled from the parts' results in ``ctx``."""
    rows = []
    for spec in ROWS:
        ours, text, source = spec.get(ctx)
        verdict, reason = _judged(ctx, spec, ours, text)
        agrees = {"agrees": True, "differs": False}.get(verdict)
        cited = verdict in ("differs", "inconclusive")
        rows.append(
            Row(
                spec.key,
                spec.quantity,
                spec.unit,
                spec.paper,
                spec.paper_text,
                ours,
                text,
                source,
                agrees,
                reason,
                spec.link if cited else "",
                verdict,
                SECTIONS.get(spec.link, "") if cited else "",
            )
        )
    return rows


def ours_cell(row: dict) -> str:
    """Our value as the tables show it: the row's text where it has one, else the number
    (3 decimals for forces and stiffnesses and numbers below 10, else 2)."""
    ours, text, unit = row["ours"], row["ours_text"], row["unit"]
    if text or ours is None:
        return text
    digits = 3 if unit in ("N", "N/mm") or abs(ours) < 10 else 2
    return f"{ours:.{digits}f}"


def readme_table(doc: dict) -> str:
    """The README's table from a run's ``table.json`` document: each row's quantity, the
    paper's value, ours and the verdict, in the report's words."""
    out = ["| quantity | paper | bristlecrawler | verdict |", "|---|---|---|---|"]
    for r in doc["rows"]:
        cells = [f"{r['quantity']} ({r['unit']})", r["paper_text"], ours_cell(r), r["verdict"]]
        out.append("| " + " | ".join(c.replace("|", "\\|") for c in cells) + " |")
    return "\n".join(out) + "\n"
