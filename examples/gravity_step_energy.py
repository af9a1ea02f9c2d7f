"""The energy each step of the FE crawler's gravity step creates, with and without the bound.

The gravity step (step 1 of the paper's analysis) starts the crawler from its unloaded
shape. A step that ends with more energy than the loads put in has found a wrong root of
the implicit step. ``solver.energy_tol`` bounds that energy (mJ per step) in every stage;
``--unbounded`` runs the gravity step with ``solver.energy_tol = inf`` to show what the
bound prevents. ::

    python examples/gravity_step_energy.py --alpha 60
    python examples/gravity_step_energy.py --alpha 60 --unbounded
"""

from __future__ import annotations

import argparse
from dataclasses import dataclass

import jax
import numpy as np

from bristlecrawler.crawler.model import build
from bristlecrawler.crawler.runner import RunContext, RunOptions, Settle, _prepare
from bristlecrawler.scenario.convert import to_spec
from bristlecrawler.scenario.load import apply_overrides, load_scenario


@dataclass(frozen=True)
class RecordedSettle(Settle):
    """:class:`Settle` that keeps its records (the run's own clears them)."""

    def __call__(self, ctx: RunContext) -> None:
        self.setup(ctx)
        ctx.state = _prepare(ctx)
        ctx.records.append(jax.device_get(ctx.crawler.observer()(ctx.state, ctx.model.params)))
        ctx.advance(self.span(ctx), self.dt_max(ctx), self.name, check=False)


def created_per_step(alpha_deg: float, unbounded: bool = False, overrides=()) -> dict:
    """Energy created by each accepted step of the gravity step (mJ), and the settled tips."""
    sets = [f"bristle.alpha_deg={alpha_deg}", *overrides]
    if unbounded:
        sets.append("solver.energy_tol=inf")
    spec = to_spec(apply_overrides(load_scenario("paper"), sets))
    cm = build(spec)
    ctx = RunContext(cm, RunOptions(), None, t_end=0.0)
    RecordedSettle()(ctx)
    t, e = ctx.records.column("t"), ctx.records.column("energies")
    # Nothing drives the crawler while it settles: a step's balance is the change of the
    # stored, kinetic and potential energy, friction, penalty, and the damping's work.
    lost = -np.diff(e[:, :5].sum(axis=1)) - 0.5 * (e[1:, 5] + e[:-1, 5]) * np.diff(t)
    x = ctx.records.column("x")
    return {
        "steps": len(t) - 1,
        "rejected": ctx.rejected,
        "created_mJ": np.maximum(-lost, 0.0),
        "t": t[1:],
        "tip_y_mm": x[:, list(cm.tips), 1],
    }


def main(argv=None) -> dict:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--alpha", type=float, default=60.0, help="inclination, degrees")
    p.add_argument("--unbounded", action="store_true", help="solver.energy_tol = inf")
    args = p.parse_args(argv)
    r = created_per_step(args.alpha, args.unbounded)
    c = r["created_mJ"]
    i = int(np.argmax(c))
    print(
        f"alpha = {args.alpha:g} deg: {r['steps']} steps ({r['rejected']} refused); the most "
        f"energy one step created: {c[i]:.4f} mJ at t = {r['t'][i]:.4g} s; steps creating "
        f"more than 0.01 mJ: {int(np.sum(c > 0.01))}; highest tip: "
        f"{r['tip_y_mm'].max():.3f} mm"
    )
    return r


if __name__ == "__main__":
    main()
