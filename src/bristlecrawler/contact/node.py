"""A contact node on a rigid substrate: the projection composed with the Coulomb kernel.

This is the piece an FE solver calls per contact node (node-to-analytic-surface contact,
Wriggers 2006, Sec. 4.1): ``x`` is the current position of the node (mm), ``anchor`` its
stick anchor in the arc-length coordinate of the substrate. Vectorise with ``jax.vmap``
over nodes (``in_axes=(0, 0, None, None)``).

``radius`` (mm, >= 0) makes the node a disc: the gap is the signed distance of the node
minus the radius, i.e. contact with the substrate offset by ``radius``. A beam node with
``radius = h/2`` touches the substrate with the beam's surface rather than its axis (the
envelope of the discs along a beam approximates its faces; a disc rolls over a land corner
with the contact normal turning continuously). Friction acts on the node's translation;
the moment of the friction force about the node (arm ``radius``) is neglected.
"""

from __future__ import annotations

import jax
import jax.numpy as jnp

from bristlecrawler.contact.coulomb import CoulombStep, FrictionLaw
from bristlecrawler.contact.profile import project


def _gs(x: jax.Array, substrate, radius=0.0) -> jax.Array:
    pr = project(substrate, x)
    return jnp.stack([pr.gap - radius, pr.arc_length])


def node_potential(x, anchor, substrate, law: FrictionLaw, lambda_n=0.0, radius=0.0) -> jax.Array:
    """Incremental contact potential of one node at ``x`` (2,), mJ.

    ``jax.grad`` w.r.t. ``x`` is the contact contribution to the internal-force vector
    (the substrate pushes the node with minus it); ``jax.hessian`` the symmetric tangent
    with the normal force frozen in the friction term.
    """
    g, s = _gs(x, substrate, radius)
    return law.potential(g, s, anchor, lambda_n)


def node_force(
    x, anchor, substrate, law: FrictionLaw, lambda_n=0.0, radius=0.0, mode=None
) -> jax.Array:
    """Contact contribution to the internal-force vector of a node, ``dPhi/dx``, N, (2,).

    Exact for the non-associative law, so ``jax.jacfwd`` of it w.r.t. ``x`` is the
    consistent non-symmetric tangent (N/mm). ``mode``: a frozen status
    (:func:`~bristlecrawler.contact.coulomb.return_map`).
    """
    pr = project(substrate, x)
    fg, fs = law.forces(pr.gap - radius, pr.arc_length, anchor, lambda_n, mode)
    return fg * pr.normal + fs * pr.arc_gradient  # grad g = n, grad s in closed form


def node_step(
    x, anchor, substrate, law: FrictionLaw, lambda_n=0.0, radius=0.0
) -> tuple[jax.Array, CoulombStep]:
    """Accept a converged step: ``(new_anchor, CoulombStep)`` for a node at ``x``."""
    g, s = _gs(x, substrate, radius)
    step = law.step(g, s, anchor, lambda_n)
    return step.anchor, step
