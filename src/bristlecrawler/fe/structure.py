"""Build a planar structure from parts: beam chains, masses, bodies, springs, links, supports.

Reads like the physics (cf. PyElastica's ``add_forcing_to``)::

    s = Structure()
    body = s.node(0.0, 0.0)                      # crawler body, left end
    s.rigid_body(body, mass=27.5e-6, inertia=0.0)
    right = s.node(100.0, 0.0)
    s.rigid_link(right, body, stretch=Sin2(-20.0, 20.0))   # bar of length 100 - s(t)
    ...
    model = s.build()

Every check happens here, before any solve, and fails with one-line
:class:`~bristlecrawler.errors.InputError` naming the parameter.
"""

from __future__ import annotations

import dataclasses
import math

import jax.numpy as jnp
import numpy as np

from bristlecrawler.errors import InputError
from bristlecrawler.fe.model import DOF_NAMES, Model, Params, Topology
from bristlecrawler.fe.motion import as_motion
from bristlecrawler.fe.terms import node_groups

_DOF = {"x": 0, "y": 1, "theta": 2, "t": 2}


@dataclasses.dataclass(frozen=True)
class TaperedRect:
    """Rectangular section, width ``b`` (mm), thickness ``h0`` -> ``h1`` (mm) along a chain.

    E: Young's modulus (MPa); nu: Poisson's ratio (G = E / (2 (1 + nu))); rho: density
    (tonne/mm^3, 1.3 g/cm^3 = 1.3e-9); shear: include shear compliance (Timoshenko).
    """

    E: float
    b: float
    h0: float
    h1: float | None = None
    rho: float = 0.0
    nu: float = 0.3
    shear: bool = False

    def thickness(self, fraction):
        """Thickness (mm) at ``fraction`` of the chain (0 at its start, 1 at its end)."""
        h1 = self.h0 if self.h1 is None else self.h1
        return self.h0 + (h1 - self.h0) * np.asarray(fraction, dtype=float)

    def check(self) -> None:
        for name in ("E", "b", "h0"):
            if not (getattr(self, name) > 0.0 and math.isfinite(getattr(self, name))):
                raise InputError(f"section {name} must be positive, got {getattr(self, name)}")
        if self.h1 is not None and not (self.h1 > 0.0 and math.isfinite(self.h1)):
            raise InputError(f"section h1 must be positive, got {self.h1}")
        if not (self.rho >= 0.0 and math.isfinite(self.rho)):
            raise InputError(f"section rho must be >= 0, got {self.rho}")
        if not (-1.0 < self.nu <= 0.5):
            raise InputError(f"section nu must be in (-1, 0.5], got {self.nu}")


class Structure:
    """Mutable builder; :meth:`build` returns the immutable :class:`~model.Model`."""

    def __init__(self) -> None:
        self._X: list[tuple[float, float]] = []
        self._elems: list[tuple[int, int, tuple]] = []
        self._springs: list[tuple[int, int, float]] = []
        self._mass: dict[int, np.ndarray] = {}
        self._loads: list[tuple[int, tuple, object]] = []
        self._presc: dict[tuple[int, int], object] = {}
        self._links: list[tuple[int, int, object]] = []
        self._gravity = (0.0, 0.0)
        self._damping = (0.0, 0.0)
        self._terms: list[tuple[object, object]] = []
        self._lumped = False
        self._stiffness_damping = True

    # -- nodes and members -------------------------------------------------------------
    def node(self, x: float, y: float) -> int:
        """New node at (x, y) mm; returns its index."""
        if not (math.isfinite(x) and math.isfinite(y)):
            raise InputError(f"node coordinates must be finite, got ({x}, {y})")
        self._X.append((float(x), float(y)))
        return len(self._X) - 1

    @property
    def coordinates(self) -> np.ndarray:
        """Reference coordinates of the nodes so far, mm, (n_nodes, 2) (a copy)."""
        return np.asarray(self._X, dtype=float).reshape(-1, 2)

    def _check_node(self, n: int, what: str) -> None:
        if not (0 <= int(n) < len(self._X)):
            raise InputError(f"{what}: node {n} does not exist")

    def beam(self, n1: int, n2: int, section: TaperedRect, h_end: tuple | None = None) -> None:
        """One element n1 -> n2; thickness h0 -> h1 of ``section`` unless ``h_end`` given."""
        section.check()
        self._check_node(n1, "beam")
        self._check_node(n2, "beam")
        ha, hb = h_end if h_end is not None else (section.h0, section.h1 or section.h0)
        G = section.E / (2.0 * (1.0 + section.nu))
        props = (section.E, G, section.b, ha, hb, 1.0 if section.shear else 0.0, section.rho)
        self._elems.append((int(n1), int(n2), props))

    def chain(self, start, end: tuple[float, float], n: int, section: TaperedRect) -> list[int]:
        """``n`` beam elements from ``start`` (node index or (x, y) mm) to point ``end`` (mm).

        The thickness goes linearly from ``section.h0`` at ``start`` to ``section.h1`` at
        ``end``. Returns the node indices, first to last.
        """
        if int(n) < 1:
            raise InputError(f"chain n (number of elements) must be >= 1, got {n}")
        section.check()
        first = start if isinstance(start, int | np.integer) else self.node(*start)
        self._check_node(first, "chain start")
        x0 = np.asarray(self._X[first])
        x1 = np.asarray(end, dtype=float)
        if np.linalg.norm(x1 - x0) == 0.0:
            raise InputError("chain end: zero length (end coincides with start)")
        h0 = section.h0
        h1 = section.h1 if section.h1 is not None else section.h0
        nodes = [int(first)]
        for k in range(1, n + 1):
            nodes.append(self.node(*(x0 + (x1 - x0) * k / n)))
        for k in range(n):
            ha = h0 + (h1 - h0) * k / n
            hb = h0 + (h1 - h0) * (k + 1) / n
            self.beam(nodes[k], nodes[k + 1], section, h_end=(ha, hb))
        return nodes

    def spring(self, n1: int, n2: int, k: float) -> None:
        """Linear spring k (N/mm) between two nodes, rest length = reference distance."""
        self._check_node(n1, "spring")
        self._check_node(n2, "spring")
        if not (k > 0.0 and math.isfinite(k)):
            raise InputError(f"spring k must be positive, got {k}")
        self._springs.append((int(n1), int(n2), float(k)))

    # -- inertia ------------------------------------------------------------------------
    def point_mass(self, n: int, mass: float) -> None:
        """Point mass (tonne; 27.5 g = 27.5e-6 t) at node ``n``."""
        self.rigid_body(n, mass, 0.0)

    def rigid_body(self, n: int, mass: float, inertia: float) -> None:
        """Rigid body with centre at node ``n``: mass (tonne), inertia (tonne mm^2)."""
        self._check_node(n, "rigid_body")
        if not (mass >= 0.0 and inertia >= 0.0):
            raise InputError(f"rigid_body mass and inertia must be >= 0, got {mass}, {inertia}")
        m = self._mass.get(int(n), np.zeros(3))
        self._mass[int(n)] = m + np.array([mass, mass, inertia])

    def lumped_mass(self, lumped: bool = True) -> None:
        """Use row-sum lumped beam mass instead of the consistent one."""
        self._lumped = bool(lumped)

    # -- constraints --------------------------------------------------------------------
    def fix(self, n: int, dofs: str | tuple = ("x", "y", "theta")) -> None:
        """Clamp the given DOFs of node ``n`` (names 'x', 'y', 'theta') to zero."""
        for d in (dofs,) if isinstance(dofs, str) else dofs:
            self.prescribe(n, d, 0.0)

    def prescribe(self, n: int, dof: str, motion) -> None:
        """DOF ``dof`` of node ``n`` follows ``motion(t)`` (mm or rad; number = constant)."""
        self._check_node(n, "prescribe")
        if dof not in _DOF:
            raise InputError(f"prescribe dof must be one of x, y, theta, got {dof!r}")
        key = (int(n), _DOF[dof])
        if key in self._presc:
            raise InputError(f"conflicting constraints: node {n} {dof} prescribed twice")
        self._presc[key] = as_motion(motion)

    def rigid_link(self, slave: int, master: int, stretch=None) -> None:
        """Slave node moves rigidly with master: x_s = x_m + R(theta_m) d(t), theta_s = theta_m.

        d(t) is the reference offset X_s - X_m lengthened by ``stretch(t)`` (mm; e.g. the
        crawler body of length L0 - s(t) is ``stretch=Sin2(-s_max, T)``). A beam clamped to
        a body at an angle is a chain whose first node is a slave of the body node.
        """
        self._check_node(slave, "rigid_link")
        self._check_node(master, "rigid_link")
        if slave == master:
            raise InputError(f"rigid_link: node {slave} linked to itself")
        if any(s == slave for s, _, _ in self._links):
            raise InputError(f"conflicting constraints: node {slave} is slave of two rigid links")
        motion = as_motion(0.0 if stretch is None else stretch)
        self._links.append((int(slave), int(master), motion))

    # -- loads ---------------------------------------------------------------------------
    def load(
        self, n: int, fx: float = 0.0, fy: float = 0.0, moment: float = 0.0, amplitude=1.0
    ) -> None:
        """Dead point load (N, N, N mm) at node ``n`` times ``amplitude(t)`` (number or motion)."""
        self._check_node(n, "load")
        vals = (float(fx), float(fy), float(moment))
        if not all(map(math.isfinite, vals)):
            raise InputError(f"load at node {n} must be finite, got {vals}")
        self._loads.append((int(n), vals, as_motion(amplitude)))

    def gravity(self, gx: float = 0.0, gy: float = -9810.0) -> None:
        """Gravity acceleration (mm/s^2) acting on all masses."""
        self._gravity = (float(gx), float(gy))

    def damping(self, a0: float = 0.0, a1: float = 0.0) -> None:
        """Rayleigh damping C = a0 M + a1 K (a0 in 1/s, a1 in s); see :class:`dynamics.Rayleigh`."""
        if not (a0 >= 0.0 and a1 >= 0.0):
            raise InputError(f"damping a0, a1 must be >= 0, got {a0}, {a1}")
        self._damping = (float(a0), float(a1))

    def stiffness_damping(self, enabled: bool = True) -> None:
        """Whether the model may carry stiffness-proportional Rayleigh damping (a1 > 0;
        default True). False leaves the product K_T v, a JVP of the internal force, and
        its second derivatives in the Newton tangent out of the compiled programs (9-15 %
        of a Newton iteration of the paper crawler in paired runs); the model
        then refuses a1 != 0 (:meth:`Model.with_params`) and a step that meets one
        anyway fails with a fatal status."""
        self._stiffness_damping = bool(enabled)

    def add_term(self, term, params=()) -> None:
        """Extra residual term (contact, ...), see :mod:`bristlecrawler.fe.terms`; the node
        groups it declares with ``couplings()`` widen the tangent's band at :meth:`build`."""
        from bristlecrawler.fe.terms import Term

        if not isinstance(term, Term):
            raise InputError(
                f"an extra term must subclass bristlecrawler.fe.Term, got {type(term).__name__}"
            )
        self._terms.append((term, params))

    # -- assembly -----------------------------------------------------------------------
    def build(self) -> Model:
        """Validate and return the :class:`Model` (raises InputError on bad input)."""
        nn = len(self._X)
        if nn == 0:
            raise InputError("structure has no nodes")
        X = np.asarray(self._X, dtype=float)
        for i, (a, b, _) in enumerate(self._elems):
            if np.linalg.norm(X[b] - X[a]) <= 1e-12 * max(1.0, np.abs(X).max()):
                raise InputError(f"beam element {i} (nodes {a}-{b}) has zero length")
        for i, (a, b, _) in enumerate(self._springs):
            if np.linalg.norm(X[b] - X[a]) == 0.0:
                raise InputError(f"spring {i} (nodes {a}-{b}) has zero rest length")
        if self._damping[1] != 0.0 and not self._stiffness_damping:
            raise InputError(
                f"damping a1 = {self._damping[1]:g} s, but stiffness_damping(False) was set"
            )
        slaves = {s for s, _, _ in self._links}
        for n, d in self._presc:
            if n in slaves:
                raise InputError(
                    f"conflicting constraints: node {n} {DOF_NAMES[d]} is prescribed "
                    "and also slave of a rigid link"
                )
        levels = _link_levels(self._links)
        _check_connected(nn, self._elems, self._springs, self._links)
        groups = [g for term, _ in self._terms for g in node_groups(term)]
        for g in groups:
            bad = [n for n in g if not 0 <= n < nn]
            if bad:
                raise InputError(f"a term couples node {bad[0]}, which does not exist")
        red_nodes, red, n_int, bs = _ordering(
            nn, self._elems, self._springs, self._links, self._presc, groups
        )
        topo = Topology(
            n_nodes=nn,
            elems=tuple((a, b) for a, b, _ in self._elems),
            springs=tuple((a, b) for a, b, _ in self._springs),
            load_nodes=tuple(n for n, _, _ in self._loads),
            presc=tuple(self._presc),
            links=tuple((s, m) for s, m, _ in self._links),
            link_levels=levels,
            red=red,
            n_interior=n_int,
            n_border=len(red) - n_int,
            bs=bs,
            stiffness_damping=self._stiffness_damping,
        )
        del red_nodes
        mass = np.zeros((nn, 3))
        for n, m in self._mass.items():
            mass[n] = m
        f64 = jnp.float64
        params = Params(
            X=jnp.asarray(X, f64),
            sec=jnp.asarray([e[2][:6] for e in self._elems] or np.zeros((0, 6)), f64),
            rho=jnp.asarray([e[2][6] for e in self._elems], f64),
            lumped=jnp.asarray(1.0 if self._lumped else 0.0, f64),
            node_mass=jnp.asarray(mass, f64),
            spring_k=jnp.asarray([k for _, _, k in self._springs], f64),
            load_vec=jnp.asarray([v for _, v, _ in self._loads] or np.zeros((0, 3)), f64),
            load_amp=tuple(m for _, _, m in self._loads),
            gravity=jnp.asarray(self._gravity, f64),
            presc=tuple(self._presc.values()),
            stretch=tuple(m for _, _, m in self._links),
            damping=jnp.asarray(self._damping, f64),
            extra=tuple(p for _, p in self._terms),
        )
        return Model(topo, params, tuple(t for t, _ in self._terms))


def _link_levels(links) -> tuple[tuple[int, ...], ...]:
    """Group links so that every master is final before its slaves are placed."""
    master_of = {s: m for s, m, _ in links}
    depth: dict[int, int] = {}

    def level(n: int, seen: tuple[int, ...]) -> int:
        if n not in master_of:
            return 0
        if n in seen:
            raise InputError(f"conflicting constraints: rigid links form a cycle through node {n}")
        if n not in depth:
            depth[n] = 1 + level(master_of[n], (*seen, n))
        return depth[n]

    groups: dict[int, list[int]] = {}
    for i, (s, _, _) in enumerate(links):
        groups.setdefault(level(s, ()), []).append(i)
    return tuple(tuple(groups[k]) for k in sorted(groups))


def _check_connected(nn, elems, springs, links) -> None:
    parent = list(range(nn))

    def find(i: int) -> int:
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    for a, b, *_ in (*elems, *springs, *links):
        parent[find(a)] = find(b)
    root = find(0)
    for n in range(nn):
        if find(n) != root:
            raise InputError(
                f"disconnected structure: node {n} is not joined to node 0 by beams, springs "
                "or rigid links"
            )


def _ordering(nn, elems, springs, links, presc, groups=()):
    """Reduced DOFs in solver order: chain-banded interior first, border DOFs last.

    Each free node owns its unprescribed DOFs; a slave node's DOFs belong to its master's
    owner. Nodes that couple far apart in the natural numbering (the crawler body, which
    touches the roots of both bristle chains) go to the border, greedily, until every
    remaining coupling spans at most two positions; the interior is then block tridiagonal.
    ``groups``: node groups coupled by extra terms (:func:`terms.node_groups`, e.g. the
    four outline points a corner contact reads); they do not move nodes to the border but
    widen the block size so that the tangent keeps their couplings.
    """
    master_of = {s: m for s, m, _ in links}

    def owner(n: int) -> int:
        while n in master_of:
            n = master_of[n]
        return n

    dofs_of = {
        n: [d for d in range(3) if (n, d) not in presc] for n in range(nn) if n not in master_of
    }
    red_nodes = [n for n in range(nn) if dofs_of.get(n)]
    is_red = set(red_nodes)
    nbr: dict[int, set[int]] = {n: set() for n in red_nodes}
    for a, b, *_ in (*elems, *springs):
        oa, ob = owner(a), owner(b)
        if oa in is_red and ob in is_red and oa != ob:
            nbr[oa].add(ob)
            nbr[ob].add(oa)
    interior = list(red_nodes)
    border: list[int] = []
    while interior:
        pos = {n: i for i, n in enumerate(interior)}
        span = {
            n: max((abs(pos[n] - pos[m]) for m in nbr[n] if m in pos), default=0) for n in interior
        }
        worst = max(interior, key=lambda n: (span[n], len(nbr[n])))
        if span[worst] <= 2:
            break
        interior.remove(worst)
        border.append(worst)
    red = [(n, d) for n in interior for d in dofs_of[n]]
    n_int = len(red)
    red += [(n, d) for n in sorted(border) for d in dofs_of[n]]
    first = {}
    last = {}
    for i, (n, _) in enumerate(red[:n_int]):
        first.setdefault(n, i)
        last[n] = i
    for g in groups:
        owners = {owner(n) for n in g} & is_red
        for a in owners:
            nbr[a] |= owners - {a}
    w = 0
    for n in interior:
        w = max(w, last[n] - first[n])
        for m in nbr[n]:
            if m in first:
                w = max(w, abs(last[m] - first[n]), abs(last[n] - first[m]))
    return red_nodes, tuple(red), n_int, max(w, 1)
