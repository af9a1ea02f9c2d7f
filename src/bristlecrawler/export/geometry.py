"""Geometry that leaves the toolkit: the bristle as a continuum, the substrate as an outline.

Everything here is NumPy and follows the FE model's own geometry (:mod:`crawler.model`):
the bristle's axis runs from its clamp to its tip, inclined by alpha from the vertical
with the tip trailing, and its thickness tapers linearly from ``thickness_clamp`` to
``thickness_tip``; the substrate is the profile of :mod:`contact.substrates` with its
fillets as circular arcs. Units: mm.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from bristlecrawler.crawler.spec import Bristle
from bristlecrawler.errors import InputError


@dataclass(frozen=True)
class BristleMesh:
    """A structured mesh of a tapered bristle in its plane: 8-node quadrilaterals
    (quadratic, so that bending does not lock as bilinear elements do).

    Attributes:
        points: (nodes, 2) coordinates, mm.
        elements: (elements, 8) node indices: the corners counter-clockwise, then the
            mid-side nodes of the faces 1-2, 2-3, 3-4, 4-1 (the ABAQUS order).
        along, across: number of elements along the axis and through the thickness.
        flipped: the elements' corner order is mirrored (a bristle with alpha < 0), so
            that faces 1 and 3 swap sides.
    """

    points: np.ndarray
    elements: np.ndarray
    along: int
    across: int
    flipped: bool = False

    def node(self, i: int, j: int) -> int:
        """The node at row ``i`` along the axis (0 to 2 ``along``: the clamp's end face to
        the tip's, mid-side rows odd) and column ``j`` across it (0: the '-n' face, 2
        ``across``: the '+n' face, n = :meth:`Bristle.normal`)."""
        return _node_index(i, j, self.across)

    def station(self, k: int) -> np.ndarray:
        """Nodes of the end face of element row ``k`` (0: the clamp's, ``along``: the tip's)."""
        return np.array([self.node(2 * k, j) for j in range(2 * self.across + 1)])

    def face(self, side: int) -> np.ndarray:
        """Nodes of the '+n' face (side +1) or the '-n' face (side -1), clamp to tip."""
        j = 2 * self.across if side > 0 else 0
        return np.array([self.node(i, j) for i in range(2 * self.along + 1)])


def _node_index(i: int, j: int, across: int) -> int:
    """Index of refined-grid point (i, j) with the elements' centre points left out: an
    even row has 2 across + 1 points, an odd row across + 1 (the even columns)."""
    if i % 2 and j % 2:
        raise ValueError(f"({i}, {j}) is an element's centre, not a node")
    pair = (3 * across + 2) * (i // 2)
    return pair + (j if i % 2 == 0 else 2 * across + 1 + j // 2)


def bristle_mesh(b: Bristle, clamp: tuple[float, float], along: int, across: int) -> BristleMesh:
    """Mesh of bristle ``b`` whose axis starts at ``clamp`` (mm): ``along`` x ``across``
    8-node quadrilaterals, the end faces normal to the axis."""
    if along < 1 or across < 1:
        raise InputError(f"a bristle mesh needs an element each way, got {along}x{across}")
    axis = np.array([-math.sin(b.alpha), -math.cos(b.alpha)])  # clamp to tip
    n = b.normal()
    c = np.asarray(clamp, dtype=float)
    pts = []
    for i in range(2 * along + 1):
        xi = i / (2 * along)
        h = float(b.thickness(xi))
        for j in range(2 * across + 1):
            if i % 2 and j % 2:
                continue
            eta = j / (2 * across) - 0.5
            pts.append(c + xi * b.length * axis + eta * h * n)
    pts = np.asarray(pts)

    def at(i, j):
        return _node_index(i, j, across)

    elems = []
    for e in range(along):
        for k in range(across):
            i, j = 2 * e, 2 * k
            corners = [at(i, j), at(i + 2, j), at(i + 2, j + 2), at(i, j + 2)]
            mids = [at(i + 1, j), at(i + 2, j + 1), at(i + 1, j + 2), at(i, j + 1)]
            elems.append(corners + mids)
    elems = np.asarray(elems, dtype=int)
    flipped = bool(_signed_areas(pts, elems[:, :4]).min() < 0)
    if flipped:  # a mirrored bristle (alpha < 0): reverse the corners and their faces
        elems = elems[:, [3, 2, 1, 0, 6, 5, 4, 7]]
    return BristleMesh(pts, elems, along, across, flipped)


def _signed_areas(p: np.ndarray, q: np.ndarray) -> np.ndarray:
    x, y = p[q, 0], p[q, 1]
    return 0.5 * np.sum(x * np.roll(y, -1, axis=1) - np.roll(x, -1, axis=1) * y, axis=1)


@dataclass(frozen=True)
class Outline:
    """One period of a substrate's surface: straight pieces and fillet arcs.

    Attributes:
        pieces: ("line", end) or ("arc", end, centre) in order from ``start``; points (2,) mm.
        start: the first point, mm.
        period: mm.
    """

    pieces: tuple
    start: np.ndarray
    period: float


def outline(substrate) -> Outline:
    """The outline of one period of ``substrate`` (any :mod:`contact.substrates` class)."""
    prof = substrate.profile()
    v = np.asarray(prof.vertices, dtype=float)
    r = np.asarray(prof.fillets, dtype=float)
    if v.ndim != 2:
        raise InputError("a batch of substrates has no single outline; export one design")
    d = v[1:] - v[:-1]
    seg = np.linalg.norm(d, axis=1)
    keep = seg > 0
    if not keep.all():  # a zero-length segment (e.g. a sawtooth's vertical drop) carries nothing
        v = np.vstack([v[:-1][keep], v[-1:]])
        r = r[keep]
        d = v[1:] - v[:-1]
        seg = np.linalg.norm(d, axis=1)
    dh = d / seg[:, None]
    n = len(seg)
    pieces = []
    # Each vertex k < n joins segment k - 1 (cyclically) to segment k.
    t_in, t_out, centres = [], [], []
    for k in range(n):
        din, dout = dh[k - 1], dh[k]
        turn = din[0] * dout[1] - din[1] * dout[0]
        cosang = float(np.clip(din @ dout, -1.0, 1.0))
        theta = math.acos(cosang)
        if r[k] <= 0 or theta < 1e-12:
            t_in.append(v[k])
            t_out.append(v[k])
            centres.append(None)
            continue
        tang = r[k] * math.tan(0.5 * theta)
        left = np.array([-din[1], din[0]])  # the centre lies on the turning side
        side = 1.0 if turn > 0 else -1.0
        t_in.append(v[k] - tang * din)
        t_out.append(v[k] + tang * dout)
        centres.append(v[k] - tang * din + side * r[k] * left)
    shift = np.array([v[-1, 0] - v[0, 0], 0.0])
    start = t_out[0]
    for k in range(n):
        nxt = (k + 1) % n
        end_line = t_in[nxt] + (shift if nxt == 0 else 0.0)
        pieces.append(("line", end_line))
        if centres[nxt] is not None:
            off = shift if nxt == 0 else 0.0
            pieces.append(("arc", t_out[nxt] + off, centres[nxt] + off))
    return Outline(tuple(pieces), start, float(shift[0]))


def polyline(o: Outline, x0: float, x1: float, arc_points: int = 8, max_step: float = 0.05):
    """The outline as points covering x0..x1 (mm), (K, 2): lines cut into pieces of at most
    ``max_step`` mm, arcs into ``arc_points`` chords."""
    k0 = math.floor((x0 - o.start[0]) / o.period) - 1
    k1 = math.ceil((x1 - o.start[0]) / o.period) + 1
    pts = [o.start + np.array([k0 * o.period, 0.0])]
    for k in range(k0, k1):
        shift = np.array([k * o.period, 0.0])
        for piece in o.pieces:
            a = pts[-1]
            if piece[0] == "line":
                b = piece[1] + shift
                m = max(1, math.ceil(np.linalg.norm(b - a) / max_step))
                pts += [a + (b - a) * s for s in np.arange(1, m + 1) / m]
            else:
                b, c = piece[1] + shift, piece[2] + shift
                pts += list(_arc_points(a, b, c, arc_points))
    p = np.asarray(pts)
    p = p[np.concatenate([[True], np.linalg.norm(np.diff(p, axis=0), axis=1) > 1e-12])]
    inside = (p[:, 0] >= x0) & (p[:, 0] <= x1)
    idx = np.flatnonzero(inside)
    lo, hi = max(idx[0] - 1, 0), min(idx[-1] + 1, len(p) - 1)
    return p[lo : hi + 1]


def _arc_points(a, b, c, m):
    """``m`` points from a (excluded) to b (included) on the shorter arc about c."""
    ra, rb = a - c, b - c
    t0 = math.atan2(ra[1], ra[0])
    dt = math.atan2(ra[0] * rb[1] - ra[1] * rb[0], ra @ rb)
    radius = float(np.linalg.norm(ra))
    ts = t0 + dt * np.arange(1, m + 1) / m
    return c + radius * np.stack([np.cos(ts), np.sin(ts)], axis=1)


def skin(points: np.ndarray, depth: float):
    """A layer of quadrilaterals ``depth`` mm thick under the polyline ``points`` (solid
    below): the nodes (2K, 2) (the surface's K, then the offset's K) and the quads (K - 1,
    4), counter-clockwise, whose fourth face (node 4 to node 1) lies on the surface."""
    p = np.asarray(points, dtype=float)
    d = np.diff(p, axis=0)
    t = d / np.linalg.norm(d, axis=1)[:, None]
    down = np.stack([t[:, 1], -t[:, 0]], axis=1)  # into the solid (on the right)
    nv = np.vstack([down[:1], down[:-1] + down[1:], down[-1:]])
    nv /= np.linalg.norm(nv, axis=1)[:, None]
    # A mitre keeps the layer's thickness at the corners.
    cos_half = np.ones(len(p))
    cos_half[1:-1] = np.maximum(np.sum(nv[1:-1] * down[1:], axis=1), 0.2)
    q = p + (depth / cos_half)[:, None] * nv
    K = len(p)
    quads = np.array([(k, K + k, K + k + 1, k + 1) for k in range(K - 1)], dtype=int)
    nodes = np.vstack([p, q])
    if _signed_areas(nodes, quads).min() <= 0:
        raise InputError(
            f"the substrate's surface layer of {depth:g} mm folds over itself: a fillet or "
            "feature of the profile is smaller than the layer"
        )
    return nodes, quads
