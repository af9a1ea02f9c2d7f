"""Benchmark of the frictional-contact term: cost of an HHT time step with and without it.

Structure: the paper's bristle (tapered 3 -> 0.5 mm, b = 30 mm, L = 5 mm, E = 1.1 MPa) with
n elements, clamped at alpha = pi/4 with its tip on a land of the paper's grooves (1 mm
wide, 0.25 mm deep, pitch 2 mm; mu = 0.65). The clamp is lowered 0.15 mm in 10 ms and
dragged at 20 mm/s (:class:`~bristlecrawler.fe.motion.SmoothRamp`) for 40 ms, so with
contact the tip is pressed and slides. Variants: no contact term (the same beam and motion,
its tip free), one contact point at the tip, one at every node but the clamp (most of them
open; "all" computes their projection all the same, "all-broad" only for the ``ACTIVE``
lowest points, see ``SubstrateContact.active``). HHT alpha = -0.2, steps of 0.2 ms at
most, adaptive (halved when Newton fails) in the compiled loop of :class:`fe.Stepper` (no
host round trip per step). Reported after compilation (the
variants timed in turn, ten rounds, the fastest round of each): time per accepted step and
per Newton iteration (rejected steps' iterations included), and the overhead over the
variant without contact.

    python bench/bench_contact.py [--sizes 10 20 50] [--repeat 10]
"""

from __future__ import annotations

import argparse
import math
import time

import jax
import jax.numpy as jnp
import numpy as np

from bristlecrawler import fe
from bristlecrawler.contact import CoulombLaw, Grooves
from bristlecrawler.contact.term import SubstrateContact
from bristlecrawler.fe.motion import SmoothRamp
from bristlecrawler.verification.contact_beam_cases import BEAM_HHT, BRISTLE, BRISTLE_LENGTH
from bristlecrawler.verification.contact_cases import history_at

GROOVES = Grooves(width=1.0, depth=0.25, pitch=2.0, phase=0.5)
T_END, DT = 0.04, 2e-4
ACTIVE = 4
VARIANTS = ("none", "tip", "all", "all-broad")


def bristle(n: int, contact: str):
    """Model with ``contact`` in ``VARIANTS`` and its state at rest."""
    alpha = math.pi / 4
    d = BRISTLE_LENGTH * np.array([math.sin(alpha), -math.cos(alpha)])
    s = fe.Structure()
    clamp = s.node(*(-d))
    s.prescribe(clamp, "x", SmoothRamp(-0.8, T_END, 0.01))
    s.prescribe(clamp, "y", SmoothRamp(-0.15, 0.01, 0.005))
    s.fix(clamp, "theta")
    nodes = s.chain(clamp, (0.0, 0.0), n, BRISTLE)
    s.damping(2.0 * 2400.0, 0.0)  # zeta = 1 at the first bending mode (~2400 rad/s)
    every = tuple(nodes[1:])
    points = {"none": (), "tip": (nodes[-1],), "all": every, "all-broad": every}[contact]
    if points:
        term = SubstrateContact(points, active=ACTIVE if contact == "all-broad" else None)
        s.add_term(term, ())
    model = s.build()
    z = jnp.zeros((model.topology.n_nodes, 3))
    hist = ()
    if points:
        law = CoulombLaw.for_reference_load(0.65, load=1.0, design_penetration=1e-4)
        params = SubstrateContact.params(np.asarray(model.params.X), points, GROOVES, law)
        model = model.with_params(extra=(params,))
        hist = (history_at(term, z, params),)
    return model, fe.DynState(jnp.asarray(0.0), jnp.zeros(model.topology.n_red), z, z, z, hist)


def _time(state, params):
    return state.t


def prepared(n: int, contact: str):
    """Compiled run of one variant: ``go() -> (carry, failed)`` and its compile time (s)."""
    model, s0 = bristle(n, contact)
    save = fe.SaveAt(_time, 4096)
    stepper = fe.Stepper.of(model, integrator=BEAM_HHT, save=save, loop="compiled")

    def go():
        carry, _, _, failed = stepper.run(stepper.start(s0, DT), model.params, T_END, DT * 1e-4, DT)
        return jax.block_until_ready(carry), bool(failed)

    t0 = time.perf_counter()
    go()
    first = time.perf_counter() - t0
    t0 = time.perf_counter()
    go()
    return go, first - (time.perf_counter() - t0)


def timed(n: int, variants=VARIANTS, repeat: int = 5) -> dict:
    """Per-variant timings; the variants are timed in turn, ``repeat`` rounds, and the
    fastest round of each counts (so a slow spell of a shared machine hits every variant
    alike rather than one)."""
    runs = {v: prepared(n, v) for v in variants}
    walls = {v: [] for v in variants}
    last = {}
    for _ in range(repeat):
        for v, (go, _) in runs.items():
            t0 = time.perf_counter()
            last[v] = go()
            walls[v].append(time.perf_counter() - t0)
    out = {}
    for v, (_, compile_s) in runs.items():
        carry, failed = last[v]
        warm = min(walls[v])
        acc, its = int(carry.accepted), int(carry.iterations)
        ok = not failed and float(carry.state.t) >= T_END * (1 - 1e-9)
        out[v] = {
            "compile": compile_s,
            "per_step": warm / acc,
            "per_iter": warm / its,
            "iters": its / acc,
            "steps": acc,
            "rejected": int(carry.rejected),
            "ok": ok,
        }
    return out


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--sizes", type=int, nargs="*", default=[10, 20, 50])
    ap.add_argument("--repeat", type=int, default=10, help="timed rounds, the fastest counts")
    args = ap.parse_args()
    fe.enable_compilation_cache()
    print(
        f"jax {jax.__version__} on {jax.devices()[0].platform}; HHT alpha=-0.2, "
        f"dt <= {DT * 1e3:g} ms, {T_END * 1e3:g} ms of press and drag"
    )
    print(
        f"{'elements':>8} {'contact':>9} | {'steps':>5} {'cut':>4} {'iters/step':>10} | "
        f"{'ms/step':>8} {'ms/iter':>8} | {'step +%':>7} {'iter +%':>7} | {'compile s':>9}"
    )
    for n in args.sizes:
        res = timed(n, repeat=args.repeat)
        base = res["none"]
        for contact, r in res.items():
            ds = 100.0 * (r["per_step"] / base["per_step"] - 1.0)
            di = 100.0 * (r["per_iter"] / base["per_iter"] - 1.0)
            print(
                f"{n:>8} {contact:>9} | {r['steps']:>5} {r['rejected']:>4} "
                f"{r['iters']:>10.2f} | {1e3 * r['per_step']:>8.2f} "
                f"{1e3 * r['per_iter']:>8.3f} | {ds:>+7.0f} {di:>+7.0f} | "
                f"{r['compile']:>9.1f}" + ("" if r["ok"] else "  (FAILED)"),
                flush=True,
            )


if __name__ == "__main__":
    main()
