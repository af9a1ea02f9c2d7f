"""The README written beside the exported decks."""

from __future__ import annotations

from bristlecrawler.crawler.drag import DragTest
from bristlecrawler.crawler.spec import CrawlerSpec

#: Keywords of the decks that CalculiX does not read (it reads the rest).
ABAQUS_ONLY = {
    "B21": "2-D beam elements (CalculiX has only 3-D beams, expanded into bricks)",
    "*SURFACE, TYPE=SEGMENTS / *RIGID BODY, ANALYTICAL SURFACE": "analytical rigid surfaces",
    "CONN2D2 / *CONNECTOR SECTION / *CONNECTOR MOTION": "connector elements",
    "*MPC BEAM between 2-D beam nodes": "rigid links of the B21 models",
    "*MASS, ALPHA=": "mass-proportional damping of point masses",
    "*OUTPUT, HISTORY / *ENERGY OUTPUT / CTF1, CU1": (
        "history outputs (CalculiX prints with *NODE PRINT)"
    ),
}


def readme(spec: CrawlerSpec, test: DragTest, options, cont_info, crawler_info) -> str:
    """The folder's README.md: the design, each deck, the keywords and how to run them."""
    b = spec.bristles[test.bristle]
    only = "\n".join(f"- `{k}`: {v}" for k, v in ABAQUS_ONLY.items())
    return f"""# Input decks of `{spec.name}`

Written by bristlecrawler from the design's `CrawlerSpec`; generated, not edited by hand
(export again after a change). Units: mm, N, s, tonne (so MPa, t/mm^3, mJ).

The design: {len(spec.bristles)} bristles, alpha {b.alpha_deg:g} deg, length {b.length:g} mm,
thickness {b.thickness_clamp:g} -> {b.thickness_tip:g} mm, width {b.width:g} mm, E
{b.youngs_modulus:g} MPa, nu {b.poisson_ratio:g}; friction mu {spec.contact.mu:g}; substrate
`{type(spec.substrate).__name__}`.

- `drag_continuum.inp` (CalculiX and ABAQUS): the drag test of bristle {test.bristle} as
  plane-{options.plane} 8-node quadrilaterals ({options.along} x {options.across}), the substrate a
  layer of fixed elements under its surface, surface-to-surface penalty contact with
  Coulomb friction; quasi-static: two `*STATIC` steps, the weight, then the carriage's path.
- `drag_beam.inp` (ABAQUS): the same test with the paper's model, {b.elements} B21 beams
  (one section each, at its mean thickness) and an analytical rigid surface with the
  fillets as arcs; dynamic (HHT alpha {spec.solver.hht_alpha:g}) with Rayleigh damping.
- `crawler.inp` (ABAQUS): the crawler, body nodes with their masses, TRANSLATOR
  connectors driven by tables of `-s(t)`, `*MPC BEAM` links, B21 bristles, an analytical
  rigid surface; a gravity step of {crawler_info.settle:g} s, then the stroke of
  {crawler_info.stroke_time:g} s, dynamic with HHT alpha {spec.solver.hht_alpha:g}.

The drag test: load {cont_info.load:.6g} N on the carriage (the bristle's share of the
weight) and the bristle's own weight {cont_info.bristle_weight:.4g} N; the carriage's path
is the amplitude `CARRIAGE_PATH` ({len(cont_info.path[0])} knots over {cont_info.path[0][-1]:g} s).
The crawler's Rayleigh damping: {crawler_info.damping}.

What the outputs mean: the carriage's horizontal force is the total reaction `RF1` of
the node set `CLAMP` (continuum) or the node `CARRIAGE` (beam); the substrate's total
reaction is the contact force on the bristle with its sign changed. In `crawler.inp`,
Delta is `U1` of the node set `FRONT`, F_c the connectors' `CTF1`, and W_c the integral
of `CTF1` over `CU1` (summed over the connectors).

## Keywords only ABAQUS reads

{only}

## Running them

    ccx -i drag_continuum          # CalculiX: results in drag_continuum.dat and .frd
    abaqus job=crawler interactive # ABAQUS/Standard

`bristlecrawler crosscheck drag` runs CalculiX on the drag test and compares its numbers
with the toolkit's own drag test.
"""
