"""How far round-off moves an FE crawler run: the compiled and the host driver, and inputs
changed by one unit in the last place (ulp).

Runs the ``paper`` scenario (two cycles by default) with the host loop, with the compiled
loop (of :class:`fe.Stepper`, the program a batch vmaps), and with the inclination and the
friction coefficient moved by one ulp (1e-16 relative). Prints each run's net advance,
its difference from the first and its accepted steps. A batched design's difference from
its single run (``bench/bench_batch.py``) is to be read against these: a batch computes
the same formulas with other roundings.

    python bench/roundoff_sensitivity.py [--cycles 2] [--set bristle.elements=20]
"""

from __future__ import annotations

import argparse
import dataclasses
import time

import numpy as np


def cases(base):
    """(name, spec, driver) of the runs to compare, the reference first."""

    def mu(x):
        return dataclasses.replace(base, contact=dataclasses.replace(base.contact, mu=x))

    alpha = base.bristles[0].alpha_deg
    m = base.contact.mu
    return [
        ("host loop", base, "host"),
        ("compiled loop", base, "compiled"),
        (
            "alpha + 1 ulp",
            base.replace_bristles(alpha_deg=float(np.nextafter(alpha, 90.0))),
            "host",
        ),
        ("mu + 1 ulp", mu(float(np.nextafter(m, 2.0))), "host"),
        ("mu - 1 ulp", mu(float(np.nextafter(m, 0.0))), "host"),
    ]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cycles", type=int, default=2)
    ap.add_argument("--set", dest="sets", action="append", default=[])
    a = ap.parse_args()

    from bristlecrawler.crawler import RunOptions, run
    from bristlecrawler.fe import enable_compilation_cache
    from bristlecrawler.scenario.convert import to_spec
    from bristlecrawler.scenario.load import apply_overrides, load_scenario

    enable_compilation_cache()
    sc = apply_overrides(load_scenario("paper"), [*a.sets, f"actuation.cycles={a.cycles}"])
    print(f"paper, {a.cycles} cycles, {sc.bristle.elements} elements per bristle")
    head = f"{'run':>15} {'net advance mm':>16} {'difference mm':>14} {'steps':>6} {'wall s':>7}"
    print(head)
    print("-" * len(head))
    ref = None
    for name, spec, driver in cases(to_spec(sc)):
        t0 = time.perf_counter()
        h = run(spec, options=RunOptions(driver=driver))
        ref = h.net_advance if ref is None else ref
        print(
            f"{name:>15} {h.net_advance:16.9f} {h.net_advance - ref:+14.3e} "
            f"{h.stats['steps']:6d} {time.perf_counter() - t0:7.0f}",
            flush=True,
        )


if __name__ == "__main__":
    main()
