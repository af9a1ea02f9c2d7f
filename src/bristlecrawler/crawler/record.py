"""What a run records after every accepted step, and the energy check built on it.

The record of a state (:func:`observer`) holds the time, the node positions, each
segment's connector force and shortening, the energies and each tip's contact state.

Connector force: the constraint force that segment j's actuated link transmits to the
subtree beyond it (the body nodes to its right, their links and bristles),
``lambda_j = sum (M a + C v + f_int + f_c - f_ext)`` over that subtree; F_j is its
component along the segment, positive when pulling the ends together, and the connector
work is ``W_c = sum_j int F_j ds_j``.
"""

from __future__ import annotations

import dataclasses
import functools
import math
from dataclasses import dataclass

import jax
import jax.numpy as jnp
import numpy as np

from bristlecrawler.fe import assembly
from bristlecrawler.fe.programs import stored

#: Columns of a record's ``energies``: elastic, kinetic, potential energy of the loads,
#: friction dissipation, contact penalty energy (mJ), damping power (mW).
ENERGY_COLUMNS = ("elastic", "kinetic", "potential", "friction", "penalty", "damping_power")


@dataclass(frozen=True)
class EnergyCheck:
    """Energy-balance error of a step relative to its bounds, from two consecutive
    records. The error is ``dW_c - d(elastic + penalty + kinetic + potential + friction)
    - dD_damp`` with ``dW_c = sum_j (F0_j + F1_j)/2 (s1_j - s0_j)`` and ``dD_damp = (P0 +
    P1)/2 dt``, the rules the recorded series use (:func:`energy_series`), so the run's
    balance residual is the sum of these errors. Negative: energy created, bounded by
    ``tol`` (mJ); positive: energy lost, bounded by ``loss_tol`` (mJ, default no bound).

    Why: energy from nothing is a wrong root (a node turned by 2 pi, a tip pushed through
    a land edge); energy lost is what a large implicit step across a snap does (a tip
    dropping into a groove): it jumps to the new equilibrium and the integrator dissipates
    part of the released elastic energy, like an inelastic impact. Bounding the loss makes
    the steps resolve the snaps. Hashable, for the drivers' caches."""

    tol: float
    loss_tol: float = math.inf

    @staticmethod
    def error(prev, new):
        """Signed energy-balance error of the step from ``prev`` to ``new``, mJ."""
        e0, e1 = prev["energies"], new["energies"]
        work = jnp.sum(0.5 * (prev["fc"] + new["fc"]) * (new["stretch"] - prev["stretch"]))
        damp = 0.5 * (e0[5] + e1[5]) * (new["t"] - prev["t"])
        return work - jnp.sum(e1[:5] - e0[:5]) - damp

    def __call__(self, prev, new):
        e = self.error(prev, new)
        # e / inf is 0 for a finite loss; a non-finite error gives NaN, which is refused.
        return jnp.maximum(-e / self.tol, e / self.loss_tol)

    def created(self, prev, new):
        """The check of the energy created alone (losses unbounded), the gravity step's:
        this check with ``loss_tol`` = inf."""
        return dataclasses.replace(self, loss_tol=math.inf)(prev, new)


def observer(cm):
    """The record of a state, jitted once per model structure: a run of a structure
    already run in this process (a benchmark's second run, a sweep's next design) traces
    and loads nothing again."""
    m = cm.model
    index = m.terms.index(cm.contact)
    return _make_observer(m.topology, m.terms, index, cm.body, cm.subtrees, cm.tip_points)


def state_terms(state, params, topo, terms, contact_index):
    """Node positions (mm), the full residual (N, (n, 3): inertia, damping, internal,
    contact and external forces; its sum over a free subtree is the force its support
    applies), the internal (elastic) forces, the contact terms' forces, the contact term's
    history and the energies of a state (see :data:`ENERGY_COLUMNS`)."""
    # Every contact term (points, and corners against faces when present) shares the law.
    law = params.extra[contact_index].law
    u, v, a, t = state.u, state.v, state.a, state.t
    f_int, damp = assembly.internal_and_damping_force(u, v, params, topo)
    f_terms = assembly.terms_residual(u, v, t, state.history, params, terms)
    f_ext = assembly.external_force(t, 1.0, params, topo)
    full = assembly.mass_times(a, params, topo) + damp + f_int + f_terms - f_ext
    hist = state.history
    pen = sum(jnp.sum(law.stored_energy(hk.p_n, hk.f_t)) for hk in hist)
    energies = jnp.stack(
        [
            assembly.internal_energy(u, params, topo),
            assembly.kinetic_energy(v, params, topo),
            -jnp.sum(f_ext * u),
            sum(jnp.sum(hk.dissipation) for hk in hist),
            pen,
            jnp.sum(v * damp),
        ]
    )
    return params.X[:, :2] + u[:, :2], full, f_int, f_terms, hist[contact_index], energies


def tip_states(h, tip_points):
    """Each tip's contact state: slip if one of its points slips, stick if one sticks,
    else open."""
    return jnp.stack([jnp.max(h.state[np.asarray(ix)]) for ix in tip_points])


@functools.lru_cache(maxsize=16)
def _make_observer(topo, terms, contact_index, body, subtrees, tip_points):
    subs = [np.asarray(s) for s in subtrees]
    body = np.asarray(body)

    @jax.jit
    def observe(state, params):
        X = params.X
        x, full, _, _, h, energies = state_terms(state, params, topo, terms, contact_index)
        fc, stretch = [], []
        for j, sub in enumerate(subs):
            lam = jnp.sum(full[sub, :2], axis=0)
            e = x[body[j + 1]] - x[body[j]]
            e = e / jnp.linalg.norm(e)
            fc.append(-jnp.dot(lam, e))
            rest = jnp.linalg.norm(X[body[j + 1], :2] - X[body[j], :2])
            stretch.append(-(jnp.linalg.norm(x[body[j + 1]] - x[body[j]]) - rest))
        return {
            "t": state.t,
            "x": x,
            "fc": jnp.stack(fc),
            "energies": energies,
            "tip_state": tip_states(h, tip_points),
            "stretch": jnp.stack(stretch),
        }

    key = (topo, terms, contact_index, body, subtrees, tip_points)
    return stored(observe, "crawler.record.observer", *key)


def energy_series(t, fc, s, en) -> dict[str, np.ndarray]:
    """Energy series (mJ, zero at the first record) from the records: times ``t`` (s),
    segment forces ``fc`` (N, (M,) or (M, S)), shortenings ``s`` (mm, same shape) and
    ``en`` (M, 6) in the order of :data:`ENERGY_COLUMNS`. The penalty energy is part of the
    elastic energy; the connector work and the damping dissipation are trapezoidal sums,
    the rules :class:`EnergyCheck` applies to each step."""
    t, fc, s, en = (np.asarray(a, float) for a in (t, fc, s, en))
    if fc.ndim == 1:
        fc, s = fc[:, None], s[:, None]
    steps = np.sum(0.5 * (fc[1:] + fc[:-1]) * np.diff(s, axis=0), axis=1)
    work = np.concatenate([[0.0], np.cumsum(steps)])
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


class Records:
    """The records of a run's accepted steps, kept as the blocks of stacked rows that the
    drivers return (one block per driver call, not one object per step: a batch of a
    thousand five-cycle designs records millions of steps).

    ``append(row)`` adds one record (a dict of arrays), ``extend(block, k)`` the first
    ``k`` rows of a block whose arrays have a leading row axis; ``column(key)`` is one
    entry of every record stacked on a leading axis; ``last()`` the newest record."""

    def __init__(self) -> None:
        self._blocks: list[dict] = []
        self._n = 0

    def __len__(self) -> int:
        return self._n

    def __bool__(self) -> bool:
        return self._n > 0

    def append(self, row) -> None:
        self.extend(jax.tree.map(lambda x: np.asarray(x)[None], row), 1)

    def extend(self, block, k: int) -> None:
        k = int(k)
        if k > 0:
            self._blocks.append(jax.tree.map(lambda b: np.asarray(b[:k]), block))
            self._n += k

    def clear(self) -> None:
        self._blocks.clear()
        self._n = 0

    def column(self, key: str) -> np.ndarray:
        if not self._blocks:
            raise IndexError("no records")
        return np.concatenate([b[key] for b in self._blocks], axis=0)

    def last(self) -> dict:
        if not self._blocks:
            raise IndexError("no records")
        return jax.tree.map(lambda b: b[-1], self._blocks[-1])
