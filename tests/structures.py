"""The FE structures the tests share, so that each is compiled once per run of the suite.

Compiling a structure (the number of bristles and their elements, the contact options, the
stroke's form, the solver's settings) costs about a minute on a 2-core machine; the values
in its parameters (the bristles' inclination, the friction coefficient, the substrate's
phase and pitch, the stick penalty, the step bounds, the stroke's amplitude, period and
cycles) do not. A test that needs an FE run takes one of the structures below and changes
values, and the compiled programs are loaded from the run's cache folder in every later
module (``tests/conftest.py``).

* :data:`COARSE`: the paper's crawler at 4 elements per bristle, contact at the tips, a
  0.8 mm stroke in 0.4 s (``coarse_scenario``); the fast lane's one FE structure.
* :func:`paper`: the paper's crawler at the full mesh (the ``paper`` scenario).
* :func:`three_bristles`: the paper's bristles (6 elements) on a body with three, one
  6 mm stroke in 4 s.
* :func:`drag_rig`: one bristle dragged over the texture (6 elements, contact at the tip).
"""

from __future__ import annotations

import dataclasses
import functools

import numpy as np

#: Overrides of a shipped scenario that give the coarse structure. The energy check's loss
#: bound is finite so that runs check both of its sides.
COARSE = (
    "bristle.elements=4",
    "contact.nodes='tip'",
    "contact.surface=false",
    "contact.corners=false",
    "actuation.s_max=0.8",  # mm: each tip moves < 0.5 mm and stays on its land
    "actuation.period=0.4",  # s
    "actuation.cycles=1",
    "actuation.settle_time=0.2",  # s of gravity step
    "solver.energy_loss_tol=1e-2",  # mJ per step
)

#: Values that make the coarse crawler mirror symmetric: vertical bristles (the
#: ``paper-vertical`` scenario) on grooves [0.5, 1.5] + 2k mm, lands centred under both
#: tips and under x = L/2.
MIRROR = ("substrate.phase=0.5",)


def coarse_scenario(name: str = "paper", *values: str):
    """Shipped scenario ``name`` at the coarse structure, with ``values`` (assignments
    that change values only: a structural key would compile another structure)."""
    from bristlecrawler.scenario.load import apply_overrides, load_scenario

    return apply_overrides(load_scenario(name), [*COARSE, *values])


def coarse_spec(name: str = "paper", *values: str):
    """The :class:`CrawlerSpec` of :func:`coarse_scenario`."""
    from bristlecrawler.scenario.convert import to_spec

    return to_spec(coarse_scenario(name, *values))


@functools.cache
def coarse_run(name: str = "paper", *values: str):
    """(scenario, history) of one run of the coarse crawler; each distinct run once per
    process."""
    from bristlecrawler.crawler import run

    sc = coarse_scenario(name, *values)
    from bristlecrawler.scenario.convert import to_spec

    return sc, run(to_spec(sc))


def paper():
    """The paper's crawler at the full mesh (20 elements per bristle, corner contact)."""
    from bristlecrawler.crawler import CrawlerSpec

    return CrawlerSpec.paper()


def three_bristles():
    """The paper's crawler with a third bristle between the two, 6 elements per bristle,
    one 6 mm stroke in 4 s (the README's and ``examples/n_bristle_crawler.py``'s)."""
    from bristlecrawler.crawler import Actuation

    spec = dataclasses.replace(
        paper().replace_bristles(elements=6), actuation=Actuation(s_max=6.0, period=4.0, cycles=1)
    )
    return spec.with_bristles(3)


def drag_rig(spec=None, **contact):
    """``spec`` (the paper's by default) as the drag tests take it: 6 elements per
    bristle, contact at the tip's axis point, no corner term; ``contact`` replaces other
    contact fields."""
    spec = paper() if spec is None else spec
    c = dataclasses.replace(spec.contact, nodes="tip", corners=False, **contact)
    return dataclasses.replace(spec.replace_bristles(elements=6), contact=c)


def spring_drag(k=0.8, fp=0.2, fn=0.5, f0=-0.05, d=4.0, n=4001):
    """The reduced model's bristle as a drag record: a spring of stiffness k (N/mm) whose
    tip sticks until the force reaches +F_p (along) or -F_n (against), dragged along by d
    and back; it starts with a force f0 (N) held by friction."""
    from bristlecrawler.crawler.drag_analysis import DragResult

    x = np.concatenate([np.linspace(0.0, d, n), np.linspace(d, 0.0, n)[1:]])
    tip, f, state = -f0 / k, [], []
    for xi in x:
        force = k * (xi - tip)
        slipping = force > fp or force < -fn
        force = min(max(force, -fn), fp)
        tip = xi - force / k
        f.append(force)
        state.append(2 if slipping else 1)
    m = x.size
    zeros = {name: np.zeros(m) for name in ("elastic", "kinetic", "potential", "friction")}
    return DragResult(
        t=np.arange(m, dtype=float),
        x=x,
        lift=np.zeros(m),
        force_x=np.asarray(f),
        contact=np.zeros((m, 2)),
        tip=np.zeros((m, 2)),
        tip_state=np.asarray(state),
        energies=zeros | {"damping": np.zeros(m), "external": np.zeros(m)},
        pitch=1.0,
        load=1.0,
        mu=0.5,
        legs=((0, n - 1, 1), (n - 1, m - 1, -1)),
    )
