"""Reference structures shared by the FE tests and ``bench/bench_fe_core.py``.

:func:`two_bristle_crawler` is the paper's Section-3 layout without the substrate: a body
bar whose length follows 100 - s(t) mm, a point mass at each end, and at each end a rigid
vertical link to the root of a tapered bristle inclined at ``alpha`` from the vertical.
"""

from __future__ import annotations

import math

from bristlecrawler.fe import Sin2, Structure, TaperedRect

#: Shore A 40 silicone bristle of the paper (mm, MPa, tonne/mm^3).
PAPER_BRISTLE = TaperedRect(E=1.1, b=30.0, h0=3.0, h1=0.5, rho=1.3e-9, nu=0.45)


def two_bristle_crawler(
    n_per_bristle: int = 20,
    alpha: float = math.pi / 4,
    *,
    length: float = 100.0,
    link: float = 5.0,
    bristle_length: float = 5.0,
    end_mass: float = 27.5e-6,
    s_max: float = 20.0,
    period: float = 20.0,
    section: TaperedRect = PAPER_BRISTLE,
    fix_body: bool = False,
    gravity: bool = True,
    terms=(),
):
    """Build the crawler; returns (structure builder, dict of node indices).

    Left body end: rigid body (mass ``end_mass`` t, no rotational inertia) carrying the body
    DOFs (x, y, theta); right end: rigid link with stretch -s(t) = -s_max sin^2(pi t/T).
    Bristle roots hang ``link`` mm below the ends. ``fix_body`` clamps the left end (a
    supported variant without contact, for static benchmarks). ``terms``: (term, params)
    pairs added with :meth:`Structure.add_term`.
    """
    s = Structure()
    left = s.node(0.0, 0.0)
    right = s.node(length, 0.0)
    s.rigid_body(left, end_mass, 0.0)
    s.point_mass(right, end_mass)
    s.rigid_link(right, left, stretch=Sin2(-s_max, period))
    d = (bristle_length * math.sin(alpha), -bristle_length * math.cos(alpha))
    chains = []
    for end in (left, right):
        x, y = (0.0 if end == left else length), -link
        root = s.node(x, y)
        s.rigid_link(root, end)
        chains.append(s.chain(root, (x + d[0], y + d[1]), n_per_bristle, section))
    if fix_body:
        s.fix(left)
    if gravity:
        s.gravity(0.0, -9810.0)
    for term, p in terms:
        s.add_term(term, p)
    return s, {"left": left, "right": right, "chains": chains}
