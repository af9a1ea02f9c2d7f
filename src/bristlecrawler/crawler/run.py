"""Running the FE crawler: gravity settle, modal damping, stroke, and the record of it all.

Step 1 (gravity, ``settle_time`` s): dynamic settle from the reference with provisional
mass-proportional damping. Then the first resonant frequency is computed by modal analysis
at the settled state (contact tangent included) and the Rayleigh damping is set to the
scenario's ratio there (paper: 0.15, mass-proportional). Step 2: the prescribed stroke,
HHT-alpha with adaptive steps. Every accepted step is recorded by one compiled observer.

Step control: a step is cut when Newton fails, when a node turns too far or a contact
point goes too deep (:class:`fe.Integrator`), and when the step's own energy balance
(:class:`EnergyCheck`: the connector work over the step, trapezoidal rule in F_c ds,
minus the changes of the stored energies and of the dissipations) shows energy *created*
beyond ``solver.energy_tol``, or *lost* beyond ``solver.energy_loss_tol``. Energy from
nothing is a wrong root (a node turned by 2 pi, a tip pushed through a land edge): it
blew up a run with a short dt_max before the check existed. Energy lost is what a large
implicit step across a snap (a tip dropping into a groove, a face slipping off a land
edge) does: it jumps to the new equilibrium and the integrator dissipates part of the
released elastic energy, like an inelastic impact. Bounding the loss per step makes the
steps resolve the snaps, at a cost: five cycles of the paper scenario took 9162 steps and
106333 Newton iterations with a bound of 0.01 mJ (balance residual 6.2 % of W_c), 3807
and 41475 without one (8.1 %), with the advance equal to 0.002 mm
(docs/fe-crawler-investigation.md). The schema's default bound is 0.01 mJ; the `paper`
scenario lifts it and reports the loss as the run's balance residual, while the vertical
bristles of `paper-vertical` need it (unbounded, a bristle flipping over under the
reversed load lost 18 mJ in unresolved steps).

Connector force: the constraint force that the actuated link transmits to the right end's
subtree (right end, its link and bristle), ``lambda = sum (M a + C v + f_int + f_c - f_ext)``
over that subtree; F_c is its component along the body, positive when pulling the ends
together, and ``W_c = int F_c ds``.
"""

from __future__ import annotations

import functools
import math
import time
from dataclasses import dataclass

import jax
import jax.numpy as jnp
import numpy as np

from bristlecrawler.contact.profile import drawing
from bristlecrawler.crawler.history import CrawlerHistory
from bristlecrawler.crawler.model import CrawlerModel, build_crawler, stroke_duration
from bristlecrawler.errors import InputError, SolverError
from bristlecrawler.scenario.schema import Scenario


@dataclass(frozen=True)
class EnergyCheck:
    """Energy-balance error of a step relative to its bounds, from two consecutive
    observer records. The error is ``dW_c - d(elastic + penalty + kinetic + potential +
    friction) - dD_damp`` with ``dW_c = (F0 + F1)/2 (s1 - s0)`` and ``dD_damp = (P0 + P1)/2
    dt``, the rules the recorded series use (:func:`_history`), so the run's balance
    residual is the sum of these errors. Negative: energy created, bounded by ``tol``
    (mJ); positive: energy lost, bounded by ``loss_tol`` (mJ, default no bound). Hashable,
    for the drivers' caches."""

    tol: float
    loss_tol: float = math.inf

    @staticmethod
    def error(prev, new):
        """Signed energy-balance error of the step from ``prev`` to ``new``, mJ."""
        e0, e1 = prev["energies"], new["energies"]
        work = 0.5 * (prev["fc"] + new["fc"]) * (new["stretch"] - prev["stretch"])
        damp = 0.5 * (e0[5] + e1[5]) * (new["t"] - prev["t"])
        return work - jnp.sum(e1[:5] - e0[:5]) - damp

    def __call__(self, prev, new):
        e = self.error(prev, new)
        # e / inf is 0 for a finite loss; a non-finite error gives NaN, which is refused.
        return jnp.maximum(-e / self.tol, e / self.loss_tol)


@dataclass(frozen=True)
class RunOptions:
    """contact: "tip" or "all" nodes (None: the scenario's); dt0: first step, s; progress:
    show a progress bar; capacity: steps per compiled chunk; grow, easy_iterations: the
    step grows by ``grow`` after a step that took <= ``easy_iterations`` Newton iterations;
    driver: "host" (:func:`fe.make_host_driver`, the loop in Python), "compiled"
    (:func:`fe.make_driver`, one XLA loop) or "auto" (host on a CPU, compiled elsewhere: on
    a CPU both now take the same time per run, but the compiled loops take longer to
    compile and to load from the cache; see make_host_driver)."""

    contact: str | None = None
    dt0: float = 1e-3
    progress: bool | None = None
    # First-frequency estimate for the settle only (replaced by modal analysis after it).
    settle_omega: float = 200.0
    capacity: int = 512
    grow: float = 1.5
    easy_iterations: int = 4
    driver: str = "auto"

    def __post_init__(self) -> None:
        if self.driver not in ("auto", "host", "compiled"):
            raise InputError(f"driver must be 'auto', 'host' or 'compiled', got {self.driver!r}")


class _Failed(Exception):
    def __init__(self, msg, carry):
        super().__init__(msg)
        self.carry = carry


def _observer(cm: CrawlerModel):
    """The record of a state, jitted once per model structure: a run of a structure
    already run in this process (a benchmark's second run, a sweep's next design) traces
    and loads nothing again (2.1-2.4 s per run when every run built its own)."""
    m = cm.model
    return _make_observer(m.topology, m.terms, cm.left, cm.right, cm.right_subtree, cm.tip_points)


@functools.lru_cache(maxsize=16)
def _make_observer(topo, terms, L, R, right_subtree, tip_points):
    from bristlecrawler.fe import assembly

    sub = np.asarray(right_subtree)

    @jax.jit
    def observe(state, params):
        X = params.X
        # Every contact term (points, and corners against faces when present) shares the law.
        k_n, k_t = params.extra[0].law.k_n, params.extra[0].law.k_t
        u, v, a, t = state.u, state.v, state.a, state.t
        f_int, damp = assembly.internal_and_damping_force(u, v, params, topo)
        f_terms = assembly.terms_residual(u, v, t, state.history, params, terms)
        f_ext = assembly.external_force(t, 1.0, params, topo)
        full = assembly.mass_times(a, params, topo) + damp + f_int + f_terms - f_ext
        lam = jnp.sum(full[sub, :2], axis=0)
        x = X[:, :2] + u[:, :2]
        e = x[R] - x[L]
        e = e / jnp.linalg.norm(e)
        fc = -jnp.dot(lam, e)
        h = state.history[0]
        pen = sum(jnp.sum(0.5 * hk.p_n**2 / k_n + 0.5 * hk.f_t**2 / k_t) for hk in state.history)
        diss = sum(jnp.sum(hk.dissipation) for hk in state.history)
        energies = jnp.stack(
            [
                assembly.internal_energy(u, params, topo),
                assembly.kinetic_energy(v, params, topo),
                -jnp.sum(f_ext * u),
                diss,
                pen,
                jnp.sum(v * damp),  # damping power
            ]
        )
        return {
            "t": t,
            "x": x,
            "fc": fc,
            "energies": energies,
            # A tip slips if one of its points slips, sticks if one sticks, else is open.
            "tip_state": jnp.stack([jnp.max(h.state[np.asarray(ix)]) for ix in tip_points]),
            "stretch": -(jnp.linalg.norm(x[R] - x[L]) - jnp.linalg.norm(X[R, :2] - X[L, :2])),
        }

    return observe


def simulate_crawler(sc: Scenario, options: RunOptions | None = None) -> CrawlerHistory:
    """Run the scenario and return its :class:`CrawlerHistory` (raises SolverError on failure)."""
    from bristlecrawler import fe
    from bristlecrawler.fe.status import CONTACT_OVERFLOW, STEP_ERROR, describe, is_fatal
    from bristlecrawler.viz.progress import sim_progress

    opt = options or RunOptions()
    wall0 = time.perf_counter()
    cm = build_crawler(sc, contact=opt.contact)
    settle = sc.actuation.settle_time
    t_end = settle + stroke_duration(sc)
    observe = _observer(cm)
    records: list = []
    iterations = 0
    rejected = 0

    ig = fe.Integrator.hht(
        sc.solver.hht_alpha,
        rtol=sc.solver.tolerance,
        max_iter=sc.solver.max_iterations,
        stall=sc.solver.stall_iterations,
        freeze=sc.solver.freeze_iterations,
        line_search=sc.solver.line_search,
        predictor=sc.solver.predictor,
        max_penetration=sc.contact.max_penetration,
        max_correction=sc.solver.max_correction,
    )
    topo, terms = cm.model.topology, cm.model.terms
    host = opt.driver == "host" or (opt.driver == "auto" and jax.default_backend() == "cpu")
    make = fe.make_host_driver if host else fe.make_driver
    tols = (sc.solver.energy_tol, sc.solver.energy_loss_tol)
    check = EnergyCheck(*tols) if any(map(math.isfinite, tols)) else None
    driver = make(topo, terms, ig, observe, opt.capacity, opt.grow, opt.easy_iterations)
    stroke_driver = make(
        topo, terms, ig, observe, opt.capacity, opt.grow, opt.easy_iterations, check
    )

    def advance(carry, params, t_stop, dt_max, where, driver=driver):
        """Drive to ``t_stop``; every accepted step's record goes to ``records``."""
        nonlocal iterations, rejected
        while float(carry.state.t) < t_stop - 1e-9:
            it0, rej0 = int(carry.iterations), int(carry.rejected)
            carry, buf, k, failed = driver(carry, params, t_stop, sc.solver.dt_min, dt_max)
            buf, k = jax.device_get(buf), int(k)
            records.extend(jax.tree.map(lambda b, i=i: b[i], buf) for i in range(k))
            iterations += int(carry.iterations) - it0
            rejected += int(carry.rejected) - rej0
            if bool(failed):
                info = carry.info
                msg = fe.message(info, f"{where}, step {len(records)}")
                if int(carry.cause) == CONTACT_OVERFLOW:
                    k = sc.contact.active_points
                    raise _Failed(msg + f" (contact.active_points = {k})", carry)
                if is_fatal(int(carry.cause)):  # stopped at once: dt was not cut
                    raise _Failed(msg, carry)
                cause = describe(int(carry.cause))
                if int(carry.cause) == STEP_ERROR:
                    cause += ": it created more energy than solver.energy_tol = "
                    cause += f"{sc.solver.energy_tol:g} mJ or lost more than "
                    cause += f"solver.energy_loss_tol = {sc.solver.energy_loss_tol:g} mJ"
                raise _Failed(
                    msg + f"; dt cut below dt_min = {sc.solver.dt_min:g} s (last attempt: {cause})",
                    carry,
                )
            bar.update(float(carry.state.t), steps=len(records), iters=iterations)
        return carry

    with sim_progress(t_end, "crawler", opt.progress) as bar:
        # Step 1: gravity settle with provisional damping.
        bar.update(0.0, stage="compiling")
        provisional = fe.Rayleigh.from_ratio(max(sc.damping.ratio, 0.15), opt.settle_omega, "mass")
        model = provisional.apply(cm.model)
        state = fe.initial_state(model)
        compile_s = math.nan
        if host:
            # The step's compilation (or its load from the persistent cache), timed apart: one
            # call of the host driver's jitted step (same argument types) on the initial state.
            t0 = time.perf_counter()
            step = fe.make_step(topo, terms, ig)
            jax.block_until_ready(step(state, model.params, jnp.asarray(float(opt.dt0) * 1e-3)))
            compile_s = time.perf_counter() - t0
        omega1, damping = math.nan, provisional
        bar.update(0.0, stage="gravity step")
        try:
            carry = advance(
                fe.driver_start(state, opt.dt0),
                model.params,
                settle,
                min(sc.solver.dt_max, 0.01),
                "gravity step",
            )
        except _Failed as e:
            raise SolverError(f"gravity step: {e.args[0]}") from None
        records.clear()
        state = carry.state
        bar.update(settle, stage="modal analysis")
        modes = fe.modes(model, state.q, n_modes=1, t=float(state.t), history=state.history)
        omega1 = float(modes.omega[0])
        zero = 1e-6 * opt.settle_omega  # rad/s: below it the lowest mode does not resonate
        if sc.damping.kind != "explicit" and not omega1 > zero:
            w2 = float(modes.eigenvalues[0])
            if w2 < -(zero**2):
                why = (
                    f"the settled state is unstable (lowest eigenvalue of the tangent "
                    f"{w2:.3g} rad^2/s^2: the crawler rocks on its contact points)"
                )
            else:
                why = "the crawler has a free rigid-body mode (no bristle sticks)"
            raise SolverError(
                f"after the gravity step {why} at t = {float(state.t):.3g} s, so the "
                "damping cannot be set at the first resonance; lengthen "
                "actuation.settle_time or give damping a0/a1"
            )
        if sc.damping.kind == "explicit":
            damping = fe.Rayleigh(sc.damping.a0, sc.damping.a1)
        else:
            damping = fe.Rayleigh.from_ratio(sc.damping.ratio, omega1, sc.damping.kind)
        model = damping.apply(cm.model)
        records.append(jax.device_get(observe(state, model.params)))
        # Step 2: the stroke, in chunks so the progress bar moves.
        bar.update(settle, stage="")  # the stroke: steps and iterations
        chunk = max(sc.actuation.period / 20.0, 0.5)
        carry = fe.driver_start(state, float(carry.dt))
        stroke_t0, stroke_it0 = time.perf_counter(), iterations

        def history_so_far():
            # The run up to now, with the wall time (s) and Newton iterations of step 2 alone.
            stroke = (time.perf_counter() - stroke_t0, iterations - stroke_it0)
            wall = time.perf_counter() - wall0
            return _history(
                cm,
                sc,
                records,
                omega1,
                damping,
                wall,
                iterations,
                rejected,
                settle,
                compile_s,
                stroke,
            )

        t = float(state.t)
        while t < t_end - 1e-9:
            t_next = min(t + chunk, t_end)
            try:
                carry = advance(
                    carry, model.params, t_next, sc.solver.dt_max, "stroke", stroke_driver
                )
            except _Failed as e:
                err = SolverError(
                    f"stroke step near t = {float(e.carry.state.t):.4g} s: {e.args[0]}"
                )
                # The run up to the failure, for diagnosis (figures, contact states).
                err.partial = history_so_far()
                err.state = e.carry.state
                raise err from None
            t = float(carry.state.t)
    return history_so_far()


def energy_series(t, fc, s, en) -> dict[str, np.ndarray]:
    """Energy series (mJ, zero at the first record) from the observer's records: times
    ``t`` (s), connector force ``fc`` (N), shortening ``s`` (mm) and ``en`` (M, 6) =
    (elastic, kinetic, potential, friction dissipation, penalty energy, damping power
    in mW). The contact penalty energy is part of the elastic energy; the connector work
    and the damping dissipation are trapezoidal sums, the rules :class:`EnergyCheck`
    applies to each step."""
    t, fc, s, en = (np.asarray(a, float) for a in (t, fc, s, en))
    work = np.concatenate([[0.0], np.cumsum(0.5 * (fc[1:] + fc[:-1]) * np.diff(s))])
    damp_power = en[:, 5]
    damping_diss = np.concatenate(
        [[0.0], np.cumsum(0.5 * (damp_power[1:] + damp_power[:-1]) * np.diff(t))]
    )
    return {
        "elastic": en[:, 0] - en[0, 0] + en[:, 4] - en[0, 4],
        "kinetic": en[:, 1] - en[0, 1],
        "potential": en[:, 2] - en[0, 2],
        "friction": en[:, 3] - en[0, 3],
        "damping": damping_diss,
        "external": work,
    }


def _history(
    cm, sc, records, omega1, damping, wall, iterations, rejected, settle, compile_s, stroke
):
    """The :class:`CrawlerHistory` of the records; ``stroke``: (wall time, s, and Newton
    iterations of step 2 alone)."""
    t = np.array([float(r["t"]) for r in records])
    x = np.stack([np.asarray(r["x"]) for r in records])
    fc = np.array([float(r["fc"]) for r in records])
    en = np.stack([np.asarray(r["energies"]) for r in records])
    s = np.array([float(r["stretch"]) for r in records])
    tip_state = np.stack([np.asarray(r["tip_state"]) for r in records])
    energies = energy_series(t, fc, s, en)
    tips = np.stack([x[:, cm.tips[0]], x[:, cm.tips[1]]], axis=1)
    # Contact state of the tips: contact term's node order starts with the tips for "tip".
    sub = cm.model.params.extra[0].substrate
    surf = drawing(sub.profile(), x[..., 0].min() - 5.0, x[..., 0].max() + 5.0)
    period = sc.actuation.period if sc.actuation.kind == "sin2" else None
    br = sc.bristle
    thickness = np.zeros(x.shape[1])
    for chain in cm.bristles:  # clamp to tip, linear taper
        frac = np.arange(len(chain)) / (len(chain) - 1)
        thickness[list(chain)] = br.thickness_clamp + (br.thickness_tip - br.thickness_clamp) * frac
    return CrawlerHistory(
        t=t - settle,
        s=s,
        left=x[:, cm.left],
        right=x[:, cm.right],
        connector_force=fc,
        connector_work=energies["external"],
        tip_position=tips,
        tip_state=tip_state,
        energies=energies,
        frame_t=t - settle,
        frame_nodes=x,
        lines=cm.lines,
        line_kind=cm.line_kind,
        substrate_xy=np.asarray(surf),
        period=period,
        cycles=sc.actuation.cycles,
        stats={
            "wall_time_s": wall,
            "compile_time_s": compile_s,
            "steps": len(records) - 1,
            "newton_iterations": iterations,
            "rejected_steps": rejected,
            "stroke_wall_time_s": stroke[0],
            "stroke_newton_iterations": stroke[1],
            "first_frequency_hz": omega1 / (2 * math.pi),
            "rayleigh_a0": damping.a0,
            "rayleigh_a1": damping.a1,
        },
        node_thickness=thickness,
    )
