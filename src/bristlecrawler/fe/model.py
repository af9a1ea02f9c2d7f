"""The assembled structure: static topology + batched parameters.

:class:`Topology` is hashable and static (it shapes the compiled programs); :class:`Params`
is a PyTree of float64 leaves (one ``jit`` serves all designs of a topology, ``vmap`` runs a
batch of them). Both come from :class:`bristlecrawler.fe.structure.Structure.build`.

Degrees of freedom: every node carries (ux mm, uy mm, theta rad), displacements from the
reference configuration. *Full* vectors have shape (n_nodes, 3). The *reduced* vector ``q``
holds only the unknowns: DOFs that are neither prescribed nor slaved to a rigid link, in
solver order (banded interior first, then the few border DOFs; see :mod:`banded`).
"""

from __future__ import annotations

import dataclasses
from typing import Any

import jax
import numpy as np

from bristlecrawler._pytree import pytree
from bristlecrawler.errors import InputError

DOF_NAMES = ("x", "y", "theta")


@dataclasses.dataclass(frozen=True)
class Topology:
    """Static description (all tuples, hashable).

    elems, springs: node pairs; load_nodes: node of each point load; presc: (node, dof) of
    each prescribed DOF; links: (slave, master) of each rigid link; link_levels: indices into
    ``links`` grouped so masters are resolved before their slaves; red: (node, dof) of each
    reduced DOF in solver order; n_interior / n_border: sizes of the banded and border parts;
    bs: block size of the block-tridiagonal interior; stiffness_damping: whether the compiled
    programs take the Rayleigh term a1 K_T v (False: mass-proportional damping only, see
    :meth:`~bristlecrawler.fe.structure.Structure.stiffness_damping`).
    """

    n_nodes: int
    elems: tuple[tuple[int, int], ...]
    springs: tuple[tuple[int, int], ...]
    load_nodes: tuple[int, ...]
    presc: tuple[tuple[int, int], ...]
    links: tuple[tuple[int, int], ...]
    link_levels: tuple[tuple[int, ...], ...]
    red: tuple[tuple[int, int], ...]
    n_interior: int
    n_border: int
    bs: int
    stiffness_damping: bool = True

    @property
    def n_red(self) -> int:
        return len(self.red)

    @property
    def n_blocks(self) -> int:
        return max(1, -(-self.n_interior // self.bs))

    def arrays(self) -> dict[str, np.ndarray]:
        """Index arrays (numpy, trace-time constants)."""

        def arr(x, shape):
            return np.asarray(x, dtype=np.int64).reshape(shape)

        return {
            "elems": arr(self.elems, (-1, 2)),
            "springs": arr(self.springs, (-1, 2)),
            "load_nodes": arr(self.load_nodes, (-1,)),
            "presc": arr(self.presc, (-1, 2)),
            "links": arr(self.links, (-1, 2)),
            "red": arr(self.red, (-1, 2)),
        }

    def dof_label(self, i: int) -> str:
        """'node 12 theta' for reduced DOF ``i``."""
        node, dof = self.red[i]
        return f"node {node} {DOF_NAMES[dof]}"


@pytree()
class Params:
    """Numeric parameters (float64 leaves; units in brackets).

    X: (n_nodes, 2) reference positions [mm]; sec: (n_elems, 6) columns E [MPa], G [MPa],
    b [mm], h0 [mm], h1 [mm], shear switch [0/1]; rho: (n_elems,) density [t/mm^3];
    lumped: 0 consistent / 1 lumped mass; node_mass: (n_nodes, 3) point and rigid-body mass
    [t] on x and y, rotational inertia [t mm^2]; spring_k: (n_springs,) [N/mm];
    load_vec: (n_loads, 3) [N, N, N mm] times ``load_amp`` motions; gravity: (2,) [mm/s^2];
    presc: motion per prescribed DOF [mm or rad]; stretch: motion per rigid link, its
    change of length [mm]; damping: Rayleigh (a0 [1/s], a1 [s]); extra: parameters of the
    extra residual terms (contact, ...), one entry per term.
    """

    X: Any
    sec: Any
    rho: Any
    lumped: Any
    node_mass: Any
    spring_k: Any
    load_vec: Any
    load_amp: tuple
    gravity: Any
    presc: tuple
    stretch: tuple
    damping: Any
    extra: tuple


@dataclasses.dataclass(frozen=True)
class Model:
    """A structure ready to solve: ``topology`` (static), ``params`` (PyTree), ``terms``.

    ``terms`` are extra residual contributions (e.g. contact), see :mod:`terms`; their
    parameters are ``params.extra``.
    """

    topology: Topology
    params: Params
    terms: tuple = ()

    def with_params(self, **changes: Any) -> Model:
        """A new model with some parameter leaves replaced (same topology, no recompile).

        Raises InputError for stiffness-proportional damping (a1 != 0) on a topology built
        without it (:meth:`~bristlecrawler.fe.structure.Structure.stiffness_damping`); a
        traced value (under ``jit``) is left to the step, which refuses it with the fatal
        status UNSUPPORTED_DAMPING."""
        damping = changes.get("damping")
        if (
            damping is not None
            and not self.topology.stiffness_damping
            and not isinstance(damping, jax.core.Tracer)
        ):
            a1 = np.asarray(damping)[..., 1]
            if np.any(a1 != 0.0):
                bad = a1.flat[int(np.argmax(a1 != 0.0))]
                raise InputError(
                    f"damping a1 = {float(bad):g} s: this model was built for "
                    "mass-proportional damping only (Structure.stiffness_damping(False))"
                )
        return dataclasses.replace(self, params=dataclasses.replace(self.params, **changes))
