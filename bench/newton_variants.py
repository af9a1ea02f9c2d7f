"""Newton settings compared on the same step attempts: iterations, failures and time.

A whole run of the FE crawler takes a different solver path with every change to Newton,
so its iteration count mixes the change with where the path went. This script keeps every
stroke attempt of one run (the state it started from, the parameters and the step size),
then solves each of them again with the compiled step of each variant and prints, per
variant: Newton iterations over all attempts, attempts that fail, the iterations spent on
the attempts the recorded run found easy (at most 4 iterations), hard (more) and failed,
and the time (the sum over attempts of the fastest of ``--calls`` calls; every
``--every``-th attempt when timing).

A variant is a comma-separated list of ``NewtonOptions`` fields (``max_backtracks=4``,
``max_correction=inf``, ``freeze_iterations=2``) or ``tangent_pairs=N`` (the corner
contact's differentiated pairs per outline); an empty string is the recorded settings.
``--oracle``: instead, solve each hard attempt that converged with every contact point's
and pair's stick or slip status frozen at the values of its own solution (an upper bound
on what a friction active set could save). Nothing is asserted.

    python bench/newton_variants.py --save runs/attempts.pkl [--cycles 1] [--set k=v]
    python bench/newton_variants.py --load runs/attempts.pkl "" max_backtracks=4 \\
        [--every 4 --calls 5]
    python bench/newton_variants.py --load runs/attempts.pkl --oracle

Loading a pickle runs code from it: load only files you made.
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import pickle
import sys
import time
from pathlib import Path


def capture(scenario: str, sets: list[str]):
    """Run ``scenario`` with ``sets`` and keep every stroke attempt: (attempts, (topology,
    terms, integrator)), attempts as (state, params, dt, iterations, status) on the host."""
    import jax

    import bristlecrawler.fe.drivers as drivers
    from bristlecrawler.crawler import RunOptions, run
    from bristlecrawler.scenario.convert import to_spec
    from bristlecrawler.scenario.load import apply_overrides, load_scenario

    sc = apply_overrides(load_scenario(scenario), sets)
    settle = float(sc.actuation.settle_time)
    kept, made = [], []
    make = drivers.make_step

    def recording(*args):
        step = make(*args)
        made.append(args)

        def wrapped(state, params, dt):
            new, info = step(state, params, dt)
            if float(state.t) >= settle - 1e-9:
                rec = (state, params, dt, int(info.iterations), int(info.status))
                kept.append(jax.device_get(rec))
            return new, info

        return wrapped

    drivers.make_step = recording
    drivers.make_host_driver.cache_clear()
    try:
        run(to_spec(sc), options=RunOptions(driver="host"))
    finally:
        drivers.make_step = make
        drivers.make_host_driver.cache_clear()
    return kept, made[-1]


def variant(text: str, terms, integrator):
    """(terms, integrator) of a variant ``text`` (see the module docstring)."""
    from bristlecrawler.contact.corner import FaceCornerContact

    newton = {}
    for item in filter(None, text.split(",")):
        key, _, value = item.partition("=")
        if key == "tangent_pairs":
            terms = tuple(
                dataclasses.replace(t, tangent_pairs=int(value))
                if isinstance(t, FaceCornerContact)
                else t
                for t in terms
            )
            continue
        field = {f.name: f for f in dataclasses.fields(integrator.newton)}.get(key)
        if field is None:
            sys.exit(f"error: {key!r} is not a NewtonOptions field or tangent_pairs")
        old = getattr(integrator.newton, key)
        newton[key] = (value == "True") if isinstance(old, bool) else type(old)(value)
    nw = dataclasses.replace(integrator.newton, **newton)
    return terms, dataclasses.replace(integrator, newton=nw)


def oracle(attempts, kept, topo, terms, integrator) -> None:
    """Print the iterations of the hard attempts that converged, as recorded and with
    their stick/slip statuses frozen at their own solution's (see the module docstring)."""
    import jax.numpy as jnp

    from bristlecrawler.fe import dynamics

    step = dynamics.make_step(topo, terms, integrator)
    frozen = dataclasses.replace(
        integrator,
        newton=dataclasses.replace(
            integrator.newton, freeze_iterations=integrator.newton.max_iterations - 1
        ),
    )
    step_frozen = dynamics.make_step(topo, terms, frozen)
    before = after = n = failed = 0
    for (state, params, dt), (_, _, _, its, status) in zip(attempts, kept, strict=True):
        if status != 0 or its <= 4:
            continue
        solved, _ = step(state, params, dt)
        # Statuses are per window slot: skip the attempts whose commit moved a window.
        moved = [
            bool(jnp.any(getattr(h0, "k0", 0) != getattr(h1, "k0", 0)))
            for h0, h1 in zip(state.history, solved.history, strict=True)
        ]
        if any(moved):
            continue
        history = tuple(
            dataclasses.replace(h0, state=h1.state)
            for h0, h1 in zip(state.history, solved.history, strict=True)
        )
        _, info = step_frozen(dataclasses.replace(state, history=history), params, dt)
        n += 1
        before += its
        after += int(info.iterations)
        failed += int(info.status) != 0
    print(
        f"{n} hard attempts that converged: {before} Newton iterations as recorded, "
        f"{after} with the statuses of their own solution frozen ({failed} failed)"
    )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("variants", nargs="*", default=[""])
    g = ap.add_mutually_exclusive_group(required=True)
    g.add_argument("--save", type=Path, help="run, keep every stroke attempt in this file")
    g.add_argument("--load", type=Path, help="attempts kept by --save")
    ap.add_argument("--scenario", default="paper")
    ap.add_argument("--cycles", type=int, default=1)
    ap.add_argument("--set", dest="sets", action="append", default=[])
    ap.add_argument("--every", type=int, default=1, help="time every N-th attempt")
    ap.add_argument("--calls", type=int, default=1, help="timed calls per attempt")
    ap.add_argument("--oracle", action="store_true", help="frozen statuses of the solution")
    a = ap.parse_args()

    import jax
    import jax.numpy as jnp
    import numpy as np

    from bristlecrawler.fe import dynamics, enable_compilation_cache

    enable_compilation_cache()
    if a.save is not None:
        kept, model = capture(a.scenario, [f"actuation.cycles={a.cycles}", *a.sets])
        a.save.parent.mkdir(parents=True, exist_ok=True)
        a.save.write_bytes(pickle.dumps((kept, model)))
        print(f"kept {len(kept)} attempts in {a.save}")
        return
    kept, (topo, terms, integrator) = pickle.loads(a.load.read_bytes())
    attempts = [jax.device_put((s, p, jnp.asarray(dt))) for s, p, dt, _, _ in kept]
    rec_its = np.array([k[3] for k in kept])
    rec_ok = np.array([k[4] == 0 for k in kept])
    easy = rec_ok & (rec_its <= 4)
    if a.oracle:
        oracle(attempts, kept, topo, terms, integrator)
        return
    print(
        f"recorded: {len(kept)} attempts, {rec_its.sum()} Newton iterations, "
        f"{(~rec_ok).sum()} failed; easy {easy.sum()}, hard {(rec_ok & ~easy).sum()}"
    )
    head = (
        f"{'variant':>28} {'iterations':>10} {'failed':>6} {'on easy':>8} {'on hard':>8} "
        f"{'on failed':>9} {'time s':>7} {'ms/iter':>8}"
    )
    print(head)
    print("-" * len(head))
    for text in a.variants:
        tm, ig = variant(text, terms, integrator)
        step = dynamics.make_step(topo, tm, ig)
        its, ok, wall, timed = [], [], 0.0, 0
        for i, args in enumerate(attempts):
            best = math.inf
            for _ in range(a.calls if i % a.every == 0 else 1):
                t0 = time.perf_counter()
                new, info = step(*args)
                jax.block_until_ready(new)
                best = min(best, time.perf_counter() - t0)
            its.append(int(info.iterations))
            ok.append(int(info.status) == 0)
            if i % a.every == 0 and i > 0:  # the first call compiles
                wall += best
                timed += its[-1]
        its, ok = np.array(its), np.array(ok)
        print(
            f"{text or 'recorded':>28} {its.sum():10d} {(~ok).sum():6d} {its[easy].sum():8d} "
            f"{its[rec_ok & ~easy].sum():8d} {its[~rec_ok].sum():9d} {wall:7.2f} "
            f"{1e3 * wall / max(timed, 1):8.3f}",
            flush=True,
        )


if __name__ == "__main__":
    main()
