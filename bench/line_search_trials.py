"""How many trials Newton's line search makes in a single run, and what a batch pays.

Runs one design (default: one cycle of ``paper`` at 6 elements per bristle, the host
loop) and counts, for every correction after a step's predictor, the trials of its line
search (1: the whole correction accepted; up to ``max_backtracks + 1``). Under ``vmap``
a sequential search is a loop of as many trials as the batch's longest search, so the
script also prints the mean of the largest count among B corrections drawn from the
run's (independent draws): the trials a batch of B such designs makes per batched
iteration with ``RunOptions(batch_trials="sequential")``, against one pass of all of
them with ``"parallel"``. Nothing is asserted.

    python bench/line_search_trials.py [--scenario paper] [--set bristle.elements=6]
                                       [--widths 8 64 1024]
"""

from __future__ import annotations

import argparse
import collections


def counting(trials: list):
    """A wrapper of :func:`fe.newton._line_search` that appends (trials, predictor) of
    every search to ``trials``: a search from ``s0`` that ends at ``s`` made
    log2(s0 / s) + 1 trials (each halves the last exactly)."""
    import jax
    import jax.numpy as jnp

    import bristlecrawler.fe.newton as newton

    search = newton._line_search

    def wrapped(res, q, dq, R, F, s0, pred, o, parallel=False):
        s, Rn, Fn = search(res, q, dq, R, F, s0, pred, o, parallel)
        k = jnp.round(jnp.log2(s0 / s)).astype(int) + 1
        jax.debug.callback(lambda k, p: trials.append((int(k), bool(p))), k, pred)
        return s, Rn, Fn

    return search, wrapped


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scenario", default="paper")
    ap.add_argument("--set", dest="sets", action="append", default=[])
    ap.add_argument("--widths", type=int, nargs="+", default=[8, 64, 1024])
    a = ap.parse_args()

    import numpy as np

    import bristlecrawler.fe.newton as newton
    from bristlecrawler.crawler import RunOptions, run
    from bristlecrawler.scenario.convert import to_spec
    from bristlecrawler.scenario.load import apply_overrides, load_scenario

    sets = ["actuation.cycles=1", "bristle.elements=6", *a.sets]
    sc = apply_overrides(load_scenario(a.scenario), sets)
    spec = to_spec(sc)
    most = spec.solver.integrator(spec.contact.penetration_limit).newton.max_backtracks + 1
    trials: list = []
    search, newton._line_search = counting(trials)
    try:
        h = run(spec, options=RunOptions(driver="host"))
    finally:
        newton._line_search = search
    k = np.array([n for n, pred in trials if not pred])
    counts = collections.Counter(k.tolist())
    print(f"{a.scenario} {sets}: {h.stats['newton_iterations']} Newton iterations")
    print(
        f"{len(k)} corrections after a predictor; trials: "
        + ", ".join(f"{n}: {counts[n]}" for n in sorted(counts))
    )
    print(f"backtracked: {np.mean(k > 1):.1%}; mean trials {k.mean():.2f}")
    rng = np.random.default_rng(0)
    for b in a.widths:
        longest = rng.choice(k, size=(2000, b)).max(axis=1).mean()
        print(
            f"B = {b:5d}: a sequential search in the batch makes {longest:.2f} trials per "
            f"iteration (mean over 2000 draws), the parallel one all "
            f"{most} at once"
        )


if __name__ == "__main__":
    main()
