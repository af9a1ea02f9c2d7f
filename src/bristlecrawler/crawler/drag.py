"""Virtual drag tests: one bristle of a design, clamped to a carriage, dragged over the texture.

The bristle (its section, inclination, material), the substrate, the contact definition,
the friction and the damping are the design's. Its clamp hangs from a carriage that carries
the bristle's share of the crawler's weight: the carriage moves horizontally along a
prescribed path at a constant, quasi-static speed, is free vertically, and holds the
clamp's rotation. After the gravity step and the modal damping of the crawler runs
(:mod:`.runner`), the carriage is dragged along the grain (+x for alpha > 0), against it,
or back and forth over many grooves. Each accepted step records the carriage's push
force, the contact forces, the tip and its contact state, and the energies; the analysis
(:mod:`.drag_analysis`) reduces them to the reduced model's parameters k, F_p and F_n.
"""

from __future__ import annotations

import dataclasses
import functools
import math
from dataclasses import dataclass
from typing import Literal

import jax
import jax.numpy as jnp
import numpy as np

from bristlecrawler import fe
from bristlecrawler.crawler.batch import check_designs, run_rigs
from bristlecrawler.crawler.drag_analysis import result_of
from bristlecrawler.crawler.model import add_contact, bristle_ends, weight_share
from bristlecrawler.crawler.parts import MAX_LENGTH
from bristlecrawler.crawler.record import state_terms, tip_states
from bristlecrawler.crawler.runner import Advance, ModalDamping, Settle, SteppedStage, run_stages
from bristlecrawler.crawler.spec import CrawlerSpec
from bristlecrawler.errors import InputError
from bristlecrawler.settings import check_settings, setting

Direction = Literal["along", "against", "cycle"]


@dataclass(frozen=True)
class DragTest:
    """What a drag test does. Each setting is declared once
    (:func:`~bristlecrawler.settings.setting`), for this object's own check and for
    ``bristlecrawler drag``'s options."""

    direction: Direction = setting(  # noqa: RUF009 (a dataclasses.field, as the others)
        "cycle",
        "along the grain (+x), against it (-x), or cycle: back and forth, along first, "
        "legs legs of distance each",
    )
    distance: float = setting(
        20.0,
        "travel of each leg, mm; at least one groove pitch, at most two of the longest pitches",
        gt=0,
        le=2 * MAX_LENGTH,
    )
    speed: float = setting(
        2.0,
        "carriage speed, mm/s; quasi-static: far below the pitch times the bristle's first "
        "frequency",
        ge=1e-4,
        le=1e3,
    )
    legs: int = setting(2, "legs of a cycle", ge=2, le=10_000)
    bristle: int = setting(0, "which bristle of the design, by index", ge=0)
    load: float | None = setting(
        None,
        "vertical load on the bristle, N; 1e4 N is a tonne's weight; None: its share of the "
        "crawler's weight (body and bristles over the number of bristles)",
        gt=0,
        le=1e4,
        none=True,
    )
    resolution: float = setting(
        0.02,
        "largest carriage travel of one time step, mm; the stick phase before the first "
        "slip, F_p/k ~ 0.5 mm for the paper's bristle, then has ~25 samples",
        gt=0,
        le=MAX_LENGTH,
    )

    @property
    def ramp(self) -> float:
        """Time over which the carriage speeds up from rest or down to it, s: the speed
        follows sin^2 there, so no step of velocity shakes the carriage."""
        return min(0.5, 0.2 * self.distance / self.speed)

    def leg_times(self) -> np.ndarray:
        """Start and end of each leg, s from the start of the drag."""
        legs = 1 if self.direction != "cycle" else self.legs
        return np.arange(legs + 1) * (self.distance / self.speed + self.ramp)

    def path(self) -> tuple[np.ndarray, np.ndarray]:
        """Knots of the carriage's path: times from the start of the drag (s) and
        displacements (mm), each leg at constant speed between sin^2 ramps."""
        v, tr, d = self.speed, self.ramp, self.distance
        tau = np.linspace(0.0, tr, 17)
        up = v * (0.5 * tau - tr / (2 * np.pi) * np.sin(np.pi * tau / tr))  # from rest
        ts, xs = [], []
        sign = -1.0 if self.direction == "against" else 1.0
        for j, t0 in enumerate(self.leg_times()[:-1]):
            s = sign * (1.0 if j % 2 == 0 else -1.0)
            x0 = 0.0 if j % 2 == 0 else sign * d
            T = d / v + tr
            ts += [t0 + tau, t0 + T - tau[::-1]]
            xs += [x0 + s * up, x0 + s * (d - up[::-1])]
        t, x = np.concatenate(ts), np.concatenate(xs)
        keep = np.concatenate([[True], np.diff(t) > 1e-12])
        return t[keep], x[keep]

    @property
    def duration(self) -> float:
        return float(self.leg_times()[-1])

    def check(self, spec: CrawlerSpec) -> None:
        """InputError (one line) naming the first setting out of its declared range, or
        that does not fit the design ``spec``."""
        check_settings(self, "drag ")
        pitch = spec.substrate.period
        if self.distance < pitch:
            raise InputError(
                f"drag distance {self.distance:g} mm is shorter than one groove pitch "
                f"({pitch:g} mm): the sliding means need whole pitches"
            )
        if self.bristle >= len(spec.bristles):
            raise InputError(
                f"drag bristle {self.bristle!r} is not one of the design's "
                f"{len(spec.bristles)} bristles"
            )


def first_frequency_estimate(spec: CrawlerSpec, index: int = 0) -> float:
    """First bending frequency of the clamped bristle, Hz: the uniform cantilever's
    1.875^2 sqrt(EI / (rho A L^4)) with the mean thickness (an estimate for the speed check)."""
    b = spec.bristles[index]
    h = 0.5 * (b.thickness_clamp + b.thickness_tip)
    ei = b.youngs_modulus * b.width * h**3 / 12.0
    rho_a = b.density * b.width * h
    return 1.875**2 * math.sqrt(ei / (rho_a * b.length**4)) / (2.0 * math.pi)


def quasi_static_ratio(spec: CrawlerSpec, test: DragTest) -> float:
    """Time of the bristle's first period over the time to cross one pitch (small:
    quasi-static)."""
    return test.speed / (spec.substrate.period * first_frequency_estimate(spec, test.bristle))


@dataclass(frozen=True)
class DragModel:
    """A built drag test: the FE model (carriage, bristle, substrate) and its bookkeeping.
    ``spec`` is a one-bristle view of the design (the runner's stages read its damping,
    actuation.settle_time, solver and contact)."""

    model: object
    spec: CrawlerSpec
    test: DragTest
    clamp: int
    chain: tuple[int, ...]
    contact: object
    tip_points: tuple[tuple[int, ...], ...]
    load: float

    @property
    def body(self) -> tuple[int, ...]:
        """The carriage's node: the gravity step records how fast it still moves at its
        end (:class:`~bristlecrawler.crawler.runner.Settle`), as a crawler's body."""
        return (self.clamp,)

    def observer(self):
        m = self.model
        index = m.terms.index(self.contact)
        return _make_drag_observer(m.topology, m.terms, index, self.clamp, self.tip_points)


def build_drag(spec: CrawlerSpec, test: DragTest | None = None) -> DragModel:
    """Check the design and the test (one-line :class:`InputError`) and build the model."""
    test = test or DragTest()
    spec.check()
    test.check(spec)
    b = dataclasses.replace(spec.bristles[test.bristle], position=0.0)
    share = weight_share(spec)
    load = test.load or share
    # The bristle's penalties are sized for the crawler's weight share (as in the crawler).
    contact = dataclasses.replace(spec.contact, penalty_load=spec.contact.penalty_load or share)
    one = dataclasses.replace(spec, bristles=(b,), contact=contact)
    s = fe.Structure()
    root, tip = bristle_ends(b, contact, x=0.0)
    clamp = s.node(*root)
    if spec.gravity > 0:
        s.point_mass(clamp, load / spec.gravity)
    t, x = test.path()
    settle = spec.actuation.settle_time
    s.prescribe(clamp, "x", fe.Piecewise(jnp.asarray(t + settle), jnp.asarray(x)))
    s.fix(clamp, "theta")
    chain = tuple(s.chain(clamp, tip, b.elements, b.section()))
    s.gravity(0.0, -spec.gravity)
    s.stiffness_damping(spec.damping.stiffness_proportional)
    term, _, tip_points = add_contact(s, one, [chain], weight=share)
    return DragModel(s.build(), one, test, clamp, chain, term, tip_points, load)


@functools.lru_cache(maxsize=8)
def _make_drag_observer(topo, terms, contact_index, clamp, tip_points):
    @jax.jit
    def observe(state, params):
        x, full, f_int, f_terms, h, energies = state_terms(
            state, params, topo, terms, contact_index
        )
        # The drive's force (the carriage's inertia and damping included): the energy
        # check's connector, along the carriage's travel.
        drive = jnp.sum(full[:, :2], axis=0)
        on_bristle = -jnp.sum(f_terms[:, :2], axis=0)  # what the substrate applies
        return {
            "t": state.t,
            "x": x,
            "fc": drive[:1],
            # What the clamp transmits into the bristle: its elements' elastic force.
            "push": f_int[clamp, :2],
            "stretch": state.u[clamp, :1],
            "lift": state.u[clamp, 1],
            "contact": on_bristle,
            "energies": energies,
            "tip_state": tip_states(h, tip_points),
        }

    return observe


@dataclass(frozen=True)
class DragStage(SteppedStage):
    """Drag the carriage along the test's path, recorded step by step with steps of at
    most ``resolution`` mm of travel (in chunks of a twentieth of the path, so that
    progress moves). A stepped stage, so a batch of drag tests runs it too."""

    name: str = "drag"
    measured = True

    def span(self, ctx) -> float:
        return ctx.crawler.test.duration

    def start(self, ctx) -> None:
        ctx.report("")
        ctx.records.append(jax.device_get(ctx.crawler.observer()(ctx.state, ctx.model.params)))

    def stepping(self, ctx) -> Advance:
        test = ctx.crawler.test
        chunk = max(self.span(ctx) / 20.0, 0.5)
        dt_max = min(ctx.spec.solver.dt_max, test.resolution / test.speed)
        return Advance(self.span(ctx), chunk, dt_max, check=True)


#: A drag test's stages: the crawler's gravity step and modal damping, then the drag.
DRAG_STAGES = (Settle(), ModalDamping(), DragStage())


def drag_test(spec: CrawlerSpec, test: DragTest | None = None, *, options=None, on_progress=None):
    """Run a drag test of ``spec``'s bristle and return its :class:`DragResult`."""
    return result_of(run_stages(build_drag(spec, test), DRAG_STAGES, options, on_progress))


def drag_tests(specs, test: DragTest | None = None, *, width=None, options=None, on_progress=None):
    """The drag test ``test`` of designs of one structure (values apart: friction,
    inclination, load, ...) as one batch, in one compiled program, each design taking the
    steps of its own :func:`drag_test`. Returns (each design's :class:`DragResult` or
    None, each design's error or None); bad input is an :class:`InputError` before any
    work, as for :func:`~.batch.run_batch`."""
    specs = tuple(specs)
    width = check_designs(specs, width)
    rigs = [build_drag(s, test) for s in specs]
    ctxs, errors, _ = run_rigs(rigs, DRAG_STAGES, width, options, on_progress)
    results = [None if e is not None else result_of(c) for c, e in zip(ctxs, errors, strict=True)]
    return results, errors
