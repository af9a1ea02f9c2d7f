"""Cost of the crawler's compiled step on captured attempts: a low-noise A/B benchmark.

Whole runs of the FE crawler spread by 15-40 % on this 2-core machine from one run to the
next (docs/performance.md), more than most changes to the step gain, and two
versions of the code take different solver paths. This script times the step itself on a
fixed set of attempts instead:

1. ``--save FILE``: run ``--cycles`` of a scenario (default one cycle of ``paper``) and
   keep every ``--every``-th step attempt of the stroke: the state it started from, the
   parameters and the step size (pickled, on the host).
2. Time the compiled step on each kept attempt (the minimum of ``--calls`` calls, after one
   call to compile or load it) and print one row per attempt, the total, and the least
   squares fit ``fixed + per_iteration * iterations`` over the attempts.

``--load FILE`` skips step 1 and times the attempts of an earlier run. Saved once, the same
attempts can be timed by two versions of the code (a checkout on ``PYTHONPATH``), in
alternation, so the comparison does not depend on which solver path each version takes.
The file holds the step's inputs only, so both versions must share the model's structure.
A whole process can still run slow (one of eight alternated runs took 0.68 s where the
others took 0.47-0.57 s): compare the medians of several alternated runs.

    python bench/bench_step.py --save runs/attempts.pkl [--scenario paper] [--cycles 1]
                               [--every 10] [--calls 9] [--set section.key=value]
    python bench/bench_step.py --load runs/attempts.pkl [--calls 9]

Nothing is asserted. Loading a pickle runs code from it: load only files you made.
"""

from __future__ import annotations

import argparse
import pickle
import sys
import time
from pathlib import Path


def _capture(sc, every: int, stop: bool = False):
    """Run the scenario ``sc`` and keep every ``every``-th stroke attempt. Returns
    (attempts, step): attempts as (state, params, dt, iterations, status) on the host.
    ``stop``: end the run at its first stroke attempt (to get the compiled step only)."""
    import jax

    import bristlecrawler.fe.drivers as drivers
    from bristlecrawler.crawler import RunOptions, run
    from bristlecrawler.scenario.convert import to_spec

    settle = float(sc.actuation.settle_time)
    kept, seen, steps = [], [0], []
    make = drivers.make_step

    def recording(*args, **kw):
        step = make(*args, **kw)
        steps.append(step)

        def wrapped(state, params, dt):
            stroke = float(state.t) >= settle - 1e-9  # the gravity step ends at settle
            if stop and stroke:
                raise _Stop
            new, info = step(state, params, dt)
            if stroke:
                seen[0] += 1
                if seen[0] % every == 0:
                    rec = (state, params, dt, int(info.iterations), int(info.status))
                    kept.append(jax.device_get(rec))
            return new, info

        return wrapped

    # The host driver builds its step with drivers.make_step; a wrapper records the
    # attempts (its lru_cache is bypassed for this run, so a fresh driver is made).
    drivers.make_step = recording
    drivers.make_host_driver.cache_clear()
    try:
        run(to_spec(sc), options=RunOptions(driver="host"))
    except _Stop:
        pass
    finally:
        drivers.make_step = make
        drivers.make_host_driver.cache_clear()
    return kept, steps[-1] if steps else None


class _Stop(Exception):
    pass


def _fail(msg: str) -> None:
    print(f"error: {msg}", file=sys.stderr)
    sys.exit(2)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scenario", default="paper")
    ap.add_argument("--cycles", type=int, default=1)
    ap.add_argument("--set", dest="sets", action="append", default=[])
    ap.add_argument("--every", type=int, default=10, help="keep every N-th attempt")
    ap.add_argument("--calls", type=int, default=9, help="timed calls per attempt")
    g = ap.add_mutually_exclusive_group(required=True)
    g.add_argument("--save", type=Path, help="run, keep attempts in this file, time them")
    g.add_argument("--load", type=Path, help="time the attempts kept in this file")
    a = ap.parse_args()
    if a.every < 1 or a.calls < 1:
        _fail("--every and --calls must be >= 1")

    import jax
    import jax.numpy as jnp
    import numpy as np

    from bristlecrawler.fe import enable_compilation_cache

    enable_compilation_cache()
    from bristlecrawler.errors import InputError, SolverError
    from bristlecrawler.scenario.load import apply_overrides, load_scenario

    if a.save is not None:
        # --cycles first, so that a --set of actuation.cycles wins.
        sets = [f"actuation.cycles={a.cycles}", *a.sets]
        try:
            sc = apply_overrides(load_scenario(a.scenario), sets)  # bad input: before the run
        except InputError as e:
            _fail(str(e))
        tmp = a.save.with_name(a.save.name + ".part")
        try:  # an unusable path: before the run, not after it
            a.save.parent.mkdir(parents=True, exist_ok=True)
            if a.save.is_dir():
                raise IsADirectoryError(f"{a.save} is a folder")
            tmp.write_bytes(b"")
            tmp.unlink()
        except OSError as e:
            _fail(f"--save {a.save}: {e}")
        try:
            attempts, step = _capture(sc, a.every)
        except SolverError as e:
            _fail(f"the run failed: {e}")
        if not attempts or step is None:
            _fail("no stroke attempt was kept (a smaller --every?)")
        tmp.write_bytes(pickle.dumps({"scenario": a.scenario, "sets": sets, "attempts": attempts}))
        tmp.replace(a.save)
        print(f"kept {len(attempts)} attempts of {a.scenario} {sets} in {a.save}")
    else:
        if not a.load.is_file():
            _fail(f"--load {a.load}: no such file")
        try:
            saved = pickle.loads(a.load.read_bytes())
            attempts, sets = saved["attempts"], saved["sets"]
            scenario = saved["scenario"]
        except Exception as e:  # any unreadable file gets one line
            _fail(f"--load {a.load}: not a file of bench_step.py ({e})")
        if not attempts:
            _fail(f"--load {a.load}: it holds no attempts")
        # The compiled step of the saved scenario: a run of it up to its first stroke step.
        try:
            _, step = _capture(apply_overrides(load_scenario(scenario), sets), 1, stop=True)
        except (InputError, SolverError) as e:
            _fail(f"--load {a.load}: its scenario does not run here: {e}")

    head = f"{'t (s)':>9} {'dt (s)':>9} {'its':>4} {'ms':>8} {'ms/iter':>8}"
    print(head)
    print("-" * len(head))
    its, ms = [], []
    for state, params, dt, _, _ in attempts:
        # On the device before the timed calls (the pickle holds host arrays).
        state, params, dt = jax.device_put((state, params, jnp.asarray(dt)))
        new, info = step(state, params, dt)
        jax.block_until_ready(new)
        best = np.inf
        for _ in range(a.calls):
            t0 = time.perf_counter()
            new, info = step(state, params, dt)
            jax.block_until_ready(new)
            best = min(best, time.perf_counter() - t0)
        n = int(info.iterations)
        its.append(n)
        ms.append(1e3 * best)
        print(
            f"{float(state.t):9.4f} {float(dt):9.2e} {n:4d} {1e3 * best:8.2f} "
            f"{1e3 * best / max(n, 1):8.3f}"
        )
    its, ms = np.asarray(its, float), np.asarray(ms)
    fit = np.linalg.lstsq(np.vstack([np.ones_like(its), its]).T, ms, rcond=None)[0]
    print(
        f"{len(ms)} attempts, {int(its.sum())} Newton iterations: {ms.sum() / 1e3:.3f} s "
        f"(the sum of each attempt's fastest call), {ms.sum() / its.sum():.3f} ms per "
        f"iteration; fit {fit[0]:.3f} ms + {fit[1]:.3f} ms per iteration"
    )


if __name__ == "__main__":
    main()
