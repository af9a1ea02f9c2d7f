"""``bristlecrawler crosscheck drag``: the drag test in CalculiX beside the toolkit's own.

Two legs of one pitch along the grain, each run by both codes on the same design and path:
CalculiX the continuum deck of :mod:`export.drag_deck` (quasi-static), the toolkit its
dynamic beam model (:func:`crawler.drag.drag_test`).

* **flat**: the substrate replaced by a plane at the level of its lands; the tip sticks,
  then slides: the stiffness before sliding and the sliding force (mu N).
* **groove** (grooved designs): the tip starts in the middle of a groove's bottom (the
  grooves shifted for it); the bristle is held by the groove's far wall and its corner
  until it climbs out: the peak force.

The rows (:mod:`export.compare`) are read from both codes' series the same way.

Output folder (``runs/<timestamp>-crosscheck-<name>`` unless given): ``config.json``,
``meta.json``, each leg's deck and CalculiX's files (``drag_flat.inp``, ``.dat``,
``.log``; ``drag_groove.*``; ``tip_compliance.*``, the bristle alone under a
tip force), ``crosscheck.json`` (the rows, both runs' facts),
``crosscheck.md`` (the table) and ``crosscheck.png`` (force against travel).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

#: Where the tip starts across the groove's bottom, from its left wall (a fraction).
START_SHARE = 0.5


@dataclass(frozen=True)
class CrosscheckRun:
    """A finished cross-check: its rows, the facts of both runs and the folder."""

    rows: list
    facts: dict[str, Any]
    out_dir: Path | None


@dataclass(frozen=True)
class Leg:
    """One leg of the cross-check: its name, design, test and CalculiX deck."""

    name: str
    spec: Any
    test: Any
    deck: str
    info: Any


def crosscheck_test(spec):
    """The cross-check's drag test: one leg along the grain, one pitch (at least 1 mm)."""
    from bristlecrawler.crawler.drag import DragTest

    return DragTest(direction="along", distance=max(spec.substrate.period, 1.0))


def prepare(spec, plane: str = "stress") -> list[Leg]:
    """The legs, their designs and CalculiX decks (checked: InputError on a spec the deck
    cannot express), before anything runs."""
    from bristlecrawler.contact.substrates import Flat, Grooves
    from bristlecrawler.export import ContinuumOptions, continuum_deck, crosscheck_spec

    opts = ContinuumOptions(plane=plane)
    top = float(spec.substrate.profile().vertices[..., 1].max())
    flat = dataclasses.replace(spec, substrate=Flat(height=top))
    designs = [("flat", flat)]
    if isinstance(spec.substrate, Grooves):
        test = crosscheck_test(spec)
        designs.append(("groove", crosscheck_spec(spec, test, START_SHARE)))
    legs = []
    for name, design in designs:
        test = crosscheck_test(design)
        text, info = continuum_deck(design, test, opts)
        legs.append(Leg(name, design, test, text, info))
    return legs


def series_from_calculix(printed, info):
    """The drag leg of CalculiX's printed results (from the end of the load step)."""
    from bristlecrawler.export.compare import DragSeries

    force = printed[("total force", "CLAMP")]
    u = printed[("displacements", "CARRIAGE")]
    sub = printed[("total force", "SUBSTRATE_NODES")]
    keep = force.time >= info.settle - 1e-12
    scale = info.force_scale
    return DragSeries(
        x=u.values[keep, 0, 0],
        force=scale * force.values[keep, 0, 0],
        # The substrate is held in place: its reactions are the contact force on the bristle.
        contact=scale * sub.values[keep, 0, :2],
    )


def series_from_toolkit(result):
    from bristlecrawler.export.compare import DragSeries

    return DragSeries(x=result.x, force=result.force_x, contact=result.contact)


def beam_tip_compliance(b, force: float = 1e-3) -> float:
    """The toolkit's bristle, clamped, under a horizontal force ``force`` (N) at its tip:
    the tip's horizontal displacement over the force, mm/N (geometrically nonlinear, so
    the force is small)."""
    from bristlecrawler import fe

    s = fe.Structure()
    clamp = s.node(0.0, 0.0)
    s.fix(clamp)
    tip = (-b.length * math.sin(b.alpha), -b.length * math.cos(b.alpha))
    chain = s.chain(clamp, tip, b.elements, b.section())
    s.load(chain[-1], fx=force)
    result = fe.solve_static(s.build())
    return float(result.state.u[chain[-1], 0]) / force


def calculix_tip_compliance(folder: Path, b, plane: str, exe: str, force: float = 1e-3) -> float:
    """The same in CalculiX with the continuum bristle
    (:func:`export.drag_deck.tip_compliance_deck`)."""
    from bristlecrawler.export import ContinuumOptions
    from bristlecrawler.export.ccx import run_ccx
    from bristlecrawler.export.drag_deck import tip_compliance_deck

    text, _ = tip_compliance_deck(b, ContinuumOptions(plane=plane), force)
    (folder / "tip_compliance.inp").write_text(text, encoding="ascii")
    run = run_ccx(folder, "tip_compliance", exe=exe)
    u = run.printed[("displacements", "TIP")].values[-1]
    return float(np.mean(u[:, 0])) / force


def run_crosscheck(
    sc,
    plane: str = "stress",
    out: str | Path | None = None,
    progress: bool | None = None,
    command: str = "",
    replace: bool = False,
) -> CrosscheckRun:
    """Run the cross-check of scenario ``sc``'s first bristle and write its folder."""
    from bristlecrawler.export.ccx import find_ccx, run_ccx
    from bristlecrawler.export.compare import Row, compare
    from bristlecrawler.io.runs import claim_run_dir
    from bristlecrawler.jobs.drag import solve_drag
    from bristlecrawler.scenario.convert import to_spec

    legs = prepare(to_spec(sc), plane)
    exe = find_ccx()
    with claim_run_dir(out, f"crosscheck-{sc.name}", replace=replace, command=command) as run:
        config = {
            "scenario": sc.model_dump(mode="json"),
            "plane": plane,
            "legs": {
                leg.name: {
                    "drag": dataclasses.asdict(leg.test),
                    "substrate": repr(leg.spec.substrate),
                }
                for leg in legs
            },
        }
        run.write_metadata(config, command)
        series, facts = {}, {"plane": plane, "mu": legs[0].spec.contact.mu}
        for leg in legs:
            (run.path / f"drag_{leg.name}.inp").write_text(leg.deck, encoding="ascii")
            ccx = run_ccx(run.path, f"drag_{leg.name}", exe=exe)
            result = solve_drag(leg.spec, leg.test, progress)
            series[leg.name] = (
                series_from_toolkit(result),
                series_from_calculix(ccx.printed, leg.info),
            )
            facts[leg.name] = {
                "calculix_complete": ccx.complete,
                "calculix_stopped": ccx.stopped,
                "calculix_wall_s": ccx.wall_s,
                "load_N": leg.info.load,
                "bristle_weight_N": leg.info.bristle_weight,
            }
            facts["calculix_version"] = ccx.version
        groove = series.get("groove", (None, None))
        rows = compare(*series["flat"], *groove, facts["mu"])
        b = legs[0].spec.bristles[legs[0].test.bristle]
        rows.insert(
            0,
            Row(
                "elastic tip compliance",
                "mm/N",
                beam_tip_compliance(b),
                calculix_tip_compliance(run.path, b, plane, exe),
                note="clamped, horizontal force at the tip (linear)",
            ),
        )
        run.write_json("crosscheck.json", {"rows": [r.to_dict() for r in rows], **facts})
        run.results_written("crosscheck.json")
        (run.path / "crosscheck.md").write_text(table_markdown(rows))
        _figure(series, run.path / "crosscheck.png", sc.name, plane)
    return CrosscheckRun(rows, facts, run.target)


def table_markdown(rows) -> str:
    """The rows as a Markdown table (numbers to 4 digits, the difference in %)."""
    lines = [
        "| quantity | toolkit | CalculiX | difference | expected | note |",
        "|---|---|---|---|---|---|",
    ]
    for r in rows:
        exp = "" if math.isnan(r.expected) else f"{r.expected:.4g} {r.unit}"
        diff = "" if math.isnan(r.difference) else f"{100 * r.difference:+.1f} %"
        cells = (f"{r.quantity} ({r.unit})", f"{r.toolkit:.4g}", f"{r.calculix:.4g}", diff, exp)
        lines.append("| " + " | ".join((*cells, r.note)) + " |")
    return "\n".join(lines) + "\n"


def _figure(series, path: Path, name: str, plane: str) -> None:
    from bristlecrawler.viz.crosscheck import plot_crosscheck
    from bristlecrawler.viz.reduced import save_figure

    fig = plot_crosscheck(
        {leg: ((t.x, t.force), (c.x, c.force)) for leg, (t, c) in series.items()},
        labels=("bristlecrawler (beams, dynamic)", f"CalculiX (plane {plane}, static)"),
        title=f"{name}: drag tests, one pitch along the grain",
    )
    save_figure(fig, path)
