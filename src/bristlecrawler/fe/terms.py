"""Extra residual terms with history variables: the plug for contact and friction.

The residual of every solver is a sum of terms,

    R = J^T [ M a + C v + f_int(u) - f_ext(t) + sum_k r_k(u, v, t, h_k) ],

where J is the Jacobian of the constraint map (:func:`assembly.expand`) and r_k are the
extra terms (internal-force sign: a penalty contact reaction pushing a node up enters as a
negative y component). Each term is a hashable :class:`Term` (it is part of the compiled
program) with three pure methods; its numeric parameters live in ``params.extra[k]`` so
they can be batched:

* ``residual(u, v, t, history, params) -> (n_nodes, 3)`` contribution at the trial state
  (u, v full nodal displacements / velocities); ``history`` is the committed value from the
  last converged step (e.g. stick anchors for Coulomb friction, return mapping inside).
* ``init_history(topology, params) -> PyTree`` initial history.
* ``commit(u, v, t, history, params) -> PyTree`` history after a converged step.

A term may also override the hooks of :class:`Term`: ``penetration(history, params)``,
the deepest penetration (mm) of a committed history (the dynamic step rejects a
converged step where it exceeds ``Integrator.penetration_limit``,
:func:`max_penetration`); with a fixed-capacity broad phase (a non-None ``active``),
``excess(u, params) -> int``, the count beyond its capacity at a state (the solvers turn
a converged state with a non-zero
excess into the fatal status CONTACT_OVERFLOW, :func:`broad_phase_excess`).

Tangents come from autodiff of ``residual``. Sparsity contract: the contribution at node i
may depend only on the DOFs of node i (or of nodes rigidly linked to it), unless the term
declares wider couplings with ``couplings() -> tuple[tuple[int, ...], ...]``: groups of
nodes (static) such that the term couples the DOFs of nodes of one group only. The
structure includes them in its DOF ordering and block size (:meth:`Structure.add_term`),
so the banded tangent extraction (:func:`banded.extract`) sees every coupling; an
undeclared coupling outside the band is silently dropped from the tangent (Newton then
converges linearly, or not at all). Static solves call ``residual`` with v = 0.
"""

from __future__ import annotations

import abc
import functools
from typing import Any, ClassVar

import jax


class Term(abc.ABC):
    """An extra residual term (see the module docstring): subclass it and write the three
    abstract methods; the hooks below have defaults that say "none". These are every
    question the solvers ask a term, so a new contact law, a spring or a constraint is
    one subclass.

    Hooks:
        freezes: the residual takes a keyword ``freeze`` (a bool, traced or not): keep the
            committed stick/slip statuses (:func:`bristlecrawler.fe.newton.newton`).
        active: the capacity of a fixed-size broad phase (None: none), with
            :meth:`excess` counting what lies beyond it.
        couplings(): node groups whose DOFs the term couples beyond a node (and the nodes
            rigidly linked to it); the structure widens the tangent's band for them.
        penetration(history, params): the deepest penetration (mm) of a committed history,
            or None when the term has no such notion.
        excess(u, params): points beyond the broad phase's capacity at displacements ``u``.
    """

    freezes: ClassVar[bool] = False
    active: int | None = None

    @abc.abstractmethod
    def residual(self, u: Any, v: Any, t: Any, history: Any, params: Any) -> Any:
        """Contribution (n_nodes, 3) at the trial state, internal-force sign."""

    @abc.abstractmethod
    def init_history(self, topology: Any, params: Any) -> Any:
        """History at the start of a run."""

    @abc.abstractmethod
    def commit(self, u: Any, v: Any, t: Any, history: Any, params: Any) -> Any:
        """History after a converged step."""

    def couplings(self) -> tuple[tuple[int, ...], ...]:
        """Node groups coupled beyond a node (none)."""
        return ()

    def penetration(self, history: Any, params: Any) -> Any:
        """Deepest penetration (mm) of a committed history; None: not a contact term."""
        return None

    def excess(self, u: Any, params: Any) -> Any:
        """Points beyond the broad phase's capacity at ``u`` (0: no broad phase)."""
        import jax.numpy as jnp

        return jnp.asarray(0)


def node_groups(term: Term) -> tuple[tuple[int, ...], ...]:
    """The node groups a term declares with ``couplings()``."""
    return tuple(tuple(int(n) for n in g) for g in term.couplings())


@functools.lru_cache(maxsize=64)
def _init_histories_fn(topology, terms):
    # One compiled program: run op by op, the corner term's history alone cost 15 s at the
    # start of a crawler run (every primitive compiled on its own).
    return jax.jit(
        lambda extra: tuple(
            term.init_history(topology, p) for term, p in zip(terms, extra, strict=True)
        )
    )


def init_histories(model) -> tuple:
    """Initial history of every term of ``model``."""
    if not model.terms:
        return ()
    return _init_histories_fn(model.topology, model.terms)(model.params.extra)


def commit_all(terms, u, v, t, history, params) -> tuple:
    """Histories after a converged step."""
    return tuple(
        term.commit(u, v, t, h, p) for term, h, p in zip(terms, history, params.extra, strict=True)
    )


def max_penetration(terms, history, params):
    """Deepest penetration (mm) over the terms that report one (0 when none does)."""
    import jax.numpy as jnp

    depths = [
        term.penetration(h, p) for term, h, p in zip(terms, history, params.extra, strict=True)
    ]
    depths = [d for d in depths if d is not None]
    return jnp.max(jnp.stack(depths)) if depths else jnp.asarray(0.0)


def broad_phase_excess(terms, u, params):
    """Points beyond the capacity of the terms' broad phases at the full displacements
    ``u`` (a jnp int, 0 when every broad phase is exact), or None (static) when no term
    has one, so a model without a broad phase compiles no check."""
    import jax.numpy as jnp

    counts = [
        term.excess(u, p)
        for term, p in zip(terms, params.extra, strict=True)
        if term.active is not None
    ]
    return jnp.sum(jnp.stack(counts)) if counts else None


def flag_overflow(terms, u, params, status):
    """``status`` with a converged state turned into CONTACT_OVERFLOW where a broad phase
    is exceeded at ``u`` (unchanged, and no check compiled, when no term has one)."""
    import jax.numpy as jnp

    from bristlecrawler.fe.status import CONTACT_OVERFLOW, SUCCESS

    excess = broad_phase_excess(terms, u, params)
    if excess is None:
        return status
    return jnp.where((status == SUCCESS) & (excess > 0), CONTACT_OVERFLOW, status)
