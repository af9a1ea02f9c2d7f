"""Operations in the compiled programs of an FE run: the size of what XLA compiles.

Traces each program a run of the crawler calls (its step, initial acceleration, observer,
static tangent and modal mass), and the same for the drag rig of its bristle, and prints
one line per program in the form ``step: N operations``, counting the equations of every
sub-jaxpr (loop bodies and conditions, branches, inner jits) as well, and the share of the
step's equations that comes from the contact modules. Nothing is compiled.

    python bench/bench_ops.py [--scenario paper] [--set section.key=value ...]
"""

from __future__ import annotations

import argparse
from collections import Counter

import jax
import jax.numpy as jnp
from jax.extend.core import ClosedJaxpr, Jaxpr


def _sub_jaxprs(params):
    for v in params.values():
        for x in v if isinstance(v, tuple | list) else (v,):
            if isinstance(x, ClosedJaxpr):
                yield x.jaxpr
            elif isinstance(x, Jaxpr):
                yield x


def count(jaxpr, by_file: Counter | None = None) -> int:
    """Equations of ``jaxpr`` and of all its sub-jaxprs; ``by_file`` counts them by the
    source file that made each (its innermost frame in the package)."""
    n = 0
    for eqn in jaxpr.eqns:
        subs = list(_sub_jaxprs(eqn.params))
        if subs:
            n += sum(count(s, by_file) for s in subs)
        else:
            n += 1
            if by_file is not None:
                by_file[_origin(eqn)] += 1
    return n


def _origin(eqn) -> str:
    tb = eqn.source_info.traceback
    for frame in tb.frames if tb is not None else ():
        if "bristlecrawler" in frame.file_name:
            return frame.file_name.split("bristlecrawler/", 1)[1]
    return "(no package frame: derivatives, transposes)"


def _unwrap(fn):
    return getattr(fn, "fn", fn)


def programs(model, integrator, observer):
    """(name, function, arguments) of the programs a run of ``model`` compiles."""
    from bristlecrawler.fe.dynamics import DynState, _initial_acceleration_fn, make_step
    from bristlecrawler.fe.modal import mass_fn
    from bristlecrawler.fe.static import _tangent_fn
    from bristlecrawler.fe.terms import init_histories

    topo, params, terms = model.topology, model.params, model.terms
    zeros = jnp.zeros((topo.n_nodes, 3))
    hist = init_histories(model)
    like = DynState(jnp.asarray(0.0), jnp.zeros(topo.n_red), zeros, zeros, zeros, hist)
    q, t, one = like.q, jnp.asarray(0.0), jnp.asarray(1.0)
    return [
        ("step", make_step(topo, terms, integrator), (like, params, jnp.asarray(1e-3))),
        ("initial acceleration", _initial_acceleration_fn(topo, terms), (q, t, hist, params)),
        ("observer", observer, (like, params)),
        ("static tangent", _tangent_fn(topo, terms), (q, params, t, one, hist)),
        ("modal mass", mass_fn(topo), (q, params, t, one)),
    ]


def report(title: str, model, integrator, observer) -> None:
    print(title)
    for name, fn, args in programs(model, integrator, observer):
        by_file: Counter = Counter()
        n = count(jax.make_jaxpr(_unwrap(fn))(*args).jaxpr, by_file)
        print(f"  {name}: {n} operations")
        if name == "step":
            contact = sum(c for f, c in by_file.items() if f.startswith("contact/"))
            print(f"    of which contact: {contact} ({100.0 * contact / n:.0f} %)")
            for f, c in by_file.most_common(8):
                print(f"      {f}: {c}")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scenario", default="paper")
    ap.add_argument("--set", dest="sets", action="append", default=[])
    a = ap.parse_args()

    from bristlecrawler.crawler.drag import build_drag
    from bristlecrawler.crawler.model import build
    from bristlecrawler.scenario.convert import to_spec
    from bristlecrawler.scenario.load import apply_overrides, load_scenario

    spec = to_spec(apply_overrides(load_scenario(a.scenario), a.sets))
    ig = spec.solver.integrator(spec.contact.penetration_limit)
    crawler = build(spec)
    title = f"crawler ({a.scenario}, {' '.join(a.sets) or 'no overrides'})"
    report(title, crawler.model, ig, crawler.observer())
    rig = build_drag(spec)
    report("drag rig", rig.model, ig, rig.observer())


if __name__ == "__main__":
    main()
