"""An FE crawler design as the bristled model's: the same body, bristles, grooves, mu and
stroke, solved with no FE (:mod:`bristlecrawler.reduced.bristled`)."""

from __future__ import annotations

import dataclasses

import numpy as np

from bristlecrawler.contact.substrates import Flat, Grooves
from bristlecrawler.crawler.spec import CrawlerSpec
from bristlecrawler.errors import InputError
from bristlecrawler.reduced.bristled import (
    BristledDesign,
    GroovedSurface,
    PolylineSurface,
    RunOptions,
    TaperedBristle,
    run,
)
from bristlecrawler.results.metrics import RunMetrics


def _surface(substrate):
    if isinstance(substrate, Grooves):
        f = lambda name: float(np.asarray(getattr(substrate, name)))  # noqa: E731
        return GroovedSurface(
            width=f("width"),
            depth=f("depth"),
            pitch=f("pitch"),
            phase=f("phase"),
            top=f("top"),
            fillet_top=f("fillet_top"),
            fillet_bottom=f("fillet_bottom"),
        )
    if isinstance(substrate, Flat):
        h = float(np.asarray(substrate.height))
        return PolylineSurface(((0.0, h), (1.0, h)))
    raise InputError(
        f"the bristled model takes grooves or a flat substrate, not {type(substrate).__name__}"
    )


def bristled_design(spec: CrawlerSpec) -> BristledDesign:
    """The bristled model's design of ``spec`` (InputError where the model has no
    counterpart: a peristaltic gait, a sampled stroke, other substrates)."""
    a = spec.actuation
    if a.gait != "breathing" or a.history is not None:
        raise InputError("the bristled model plays the breathing sin^2 stroke only")
    if spec.contact.friction != "coulomb":
        raise InputError(
            f"the bristled model has Coulomb friction only, not contact.friction = "
            f"{spec.contact.friction}"
        )
    names = [f.name for f in dataclasses.fields(TaperedBristle)]
    bristles = tuple(TaperedBristle(**{n: getattr(b, n) for n in names}) for b in spec.bristles)
    x = spec.positions()
    return BristledDesign(
        bristles=bristles,
        places=tuple(float(v) for v in x - x[0]),
        body_mass=spec.body.mass,
        link_length=spec.body.link_length,
        free_pitch=spec.body.free_pitch,
        surface=_surface(spec.substrate),
        mu=spec.contact.mu,
        s_max=a.s_max,
        gravity=spec.gravity,
        bristle_density=spec.bristles[0].density,
        start=float(x[0]),
    )


def bristled_metrics(spec: CrawlerSpec, cycles: int | None = None) -> RunMetrics:
    """The bristled model's advance and work for ``spec`` (``cycles`` strokes, default the
    spec's). Raises
    :class:`~bristlecrawler.errors.SolverError` where its run failed."""
    from bristlecrawler.errors import SolverError

    r = run([bristled_design(spec)], cycles or spec.actuation.cycles, RunOptions())
    if not bool(r.ok[0]):
        raise SolverError(
            f"the bristled model did not settle ({int(r.unconverged[0])} equilibrium solves "
            f"failed, {int(r.stalled[0])} steps' slides did not settle)"
        )
    adv = r.advance_per_cycle[0]
    work = float(r.work[0])
    return RunMetrics(float(r.net_advance[0]), tuple(float(v) for v in adv), work)


__all__ = ["bristled_design", "bristled_metrics"]
