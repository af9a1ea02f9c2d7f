"""Where a bristle's tip can be: the path of a disc's centre over a periodic substrate.

The tip is a disc of radius r (half the tip's thickness, mm) resting on the substrate's
real outline: lands, groove walls, fillets and corners. Its centre cannot come closer than
r to the solid, so in contact it lies on the upper envelope

    g(x) = max over outline points p with |x - p_x| <= r of  p_y + sqrt(r^2 - (x - p_x)^2),

the outline's offset by r (a convex corner becomes an arc of radius r plus its fillet; a
concave corner a kink where the disc touches both faces). A :class:`TipPath` samples that
curve over one period at equal arc-length steps and gives, at arc length u (mm), the
centre and the curve's unit tangent (towards +x) and outward normal. The tangent's angle is
interpolated between the samples, so a concave corner is a bend of radius about one sample
spacing whose normals sweep the corner's whole cone: a tip pushed into it stops where its
force enters the friction cone of one of those normals. Units: mm.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass

import numpy as np

from bristlecrawler.errors import InputError


def _arc(cx, cy, r, a0, a1, n):
    a = np.linspace(a0, a1, n)
    return np.stack([cx + r * np.cos(a), cy + r * np.sin(a)], -1)


def groove_outline(
    width: float,
    depth: float,
    pitch: float,
    phase: float = 0.0,
    top: float = 0.0,
    fillet_top: float = 0.0,
    fillet_bottom: float = 0.0,
    spacing: float = 0.002,
) -> np.ndarray:
    """Points (n, 2) of one period of rectangular grooves (as
    ``contact.substrates.Grooves``: groove 0 from x = phase to phase + width, bottom at
    top - depth, fillets on the land corners and the bottom corners), from the middle of a
    land to the middle of the next, at most ``spacing`` mm apart along straight parts."""
    w, d, p, rt, rb = width, depth, pitch, fillet_top, fillet_bottom
    if not (0 < w < p and d > 0):
        raise InputError(f"grooves need 0 < width < pitch and depth > 0, got {w}, {p}, {d}")
    x0 = phase - 0.5 * (p - w)
    bot = top - d
    n_arc = 24
    pieces = [
        np.array([[x0, top]]),
        _arc(phase - rt, top - rt, rt, np.pi / 2, 0.0, n_arc),
        _arc(phase + rb, bot + rb, rb, np.pi, 1.5 * np.pi, n_arc),
        _arc(phase + w - rb, bot + rb, rb, 1.5 * np.pi, 2 * np.pi, n_arc),
        _arc(phase + w + rt, top - rt, rt, np.pi, np.pi / 2, n_arc),
        np.array([[x0 + p, top]]),
    ]
    return densify(np.vstack(pieces), spacing)


def densify(points: np.ndarray, spacing: float) -> np.ndarray:
    """The polyline ``points`` (n, 2) with points added so that none are further apart than
    ``spacing`` (mm)."""
    out = [points[:1]]
    for a, b in itertools.pairwise(points):
        n = max(1, int(np.ceil(np.hypot(*(b - a)) / spacing)))
        t = np.arange(1, n + 1)[:, None] / n
        out.append(a + t * (b - a))
    return np.vstack(out)


def _heights(outline: np.ndarray, x: np.ndarray, period: float) -> np.ndarray:
    """The outline's highest point over each of the equally spaced ``x`` (its upper
    envelope: a wall's height is its top), periodic."""
    dx = x[1] - x[0]
    h = np.full(x.size, -np.inf)
    px = (outline[:, 0] - x[0]) % period
    k = np.rint(px / dx).astype(int) % (x.size - 1)
    np.maximum.at(h, k, outline[:, 1])
    h[-1] = h[0] = max(h[0], h[-1])
    filled = np.isfinite(h)
    return np.interp(x, x[filled], h[filled])


def _envelope(outline: np.ndarray, shape: np.ndarray, x: np.ndarray, period: float):
    """g(x): the lowest the tip's reference point can be at x without any point b of its
    ``shape`` (n, 2; offsets from the reference point, mm) going below the outline:
    max over b of Y(x + b_x) - b_y, Y the outline's upper envelope."""
    grid = np.linspace(x[0], x[0] + period, 4 * (x.size - 1) + 1)
    y = _heights(outline, grid, period)
    g = np.full(x.shape, -np.inf)
    for b in shape:
        xs = (x + b[0] - grid[0]) % period + grid[0]
        g = np.maximum(g, np.interp(xs, grid, y) - b[1])
    return g


def disc_shape(radius: float, points: int = 181) -> np.ndarray:
    """The lower half of a disc of ``radius`` (mm) about the reference point, (n, 2)."""
    a = np.linspace(np.pi, 2 * np.pi, points)
    return radius * np.stack([np.cos(a), np.sin(a)], -1)


def bristle_end_shape(
    thickness_tip: float,
    taper: float,
    angle: float,
    length: float,
    spacing: float = 0.0005,
) -> np.ndarray:
    """The outline of a bristle's last ``length`` mm about its tip's axis point (n, 2):
    its two faces, thickness ``thickness_tip + 2 taper t`` at ``t`` mm from the tip, and
    the flat end between them. ``angle``: the direction of the axis towards the tip, rad."""
    e = np.array([np.cos(angle), np.sin(angle)])
    n = np.array([-e[1], e[0]])
    t = np.linspace(0.0, length, max(2, int(length / spacing) + 1))[:, None]
    half = 0.5 * thickness_tip + taper * t
    faces = [-t * e + half * n, -t * e - half * n]
    c = np.linspace(-0.5, 0.5, max(2, int(thickness_tip / spacing) + 1))[:, None]
    end = c * thickness_tip * n
    return np.vstack([*faces, end])


@dataclass(frozen=True)
class GroovedSurface:
    """Rectangular grooves in a flat land (the FE crawler's ``Grooves``), mm.

    Attributes:
        width, depth, pitch: the grooves'. phase: x of groove 0's left wall. top: the
        land's level. fillet_top, fillet_bottom: radii of the land and bottom corners.
    """

    width: float = 1.0
    depth: float = 0.25
    pitch: float = 2.0
    phase: float = 0.0
    top: float = 0.0
    fillet_top: float = 0.02
    fillet_bottom: float = 0.0

    def outline(self) -> np.ndarray:
        """Points of one period, mm (n, 2)."""
        return groove_outline(
            self.width,
            self.depth,
            self.pitch,
            self.phase,
            self.top,
            self.fillet_top,
            self.fillet_bottom,
        )


@dataclass(frozen=True)
class PolylineSurface:
    """Any periodic outline: ``points`` ((x, y), ...) of one period, mm, the last one
    period after the first at the same height (a flat is two points)."""

    points: tuple[tuple[float, float], ...]

    def outline(self) -> np.ndarray:
        """Points of one period, mm (n, 2)."""
        return densify(np.asarray(self.points, dtype=float), 0.002)


@dataclass(frozen=True)
class TipPath:
    """The disc centre's path over one period, sampled at equal arc-length steps.

    Attributes:
        pitch: the substrate's period along x, mm.
        length: the path's arc length over one period, mm.
        x, y: the samples' centres, mm, (m + 1,): the last is the first one period on.
        angle: the tangent's angle from +x at the samples, rad, (m + 1,).
    """

    pitch: float
    length: float
    x: np.ndarray
    y: np.ndarray
    angle: np.ndarray

    @classmethod
    def over(
        cls, outline: np.ndarray, shape: np.ndarray, samples: int = 2048, bend: float = 0.02
    ) -> TipPath:
        """The path of a tip of ``shape`` (points about its reference point, mm; e.g.
        :func:`disc_shape`, :func:`bristle_end_shape`) over the periodic ``outline``
        (points of one period, the last one period after the first, same height)."""
        outline = np.asarray(outline, dtype=float)
        period = float(outline[-1, 0] - outline[0, 0])
        if not (period > 0 and abs(outline[-1, 1] - outline[0, 1]) < 1e-9):
            raise InputError("an outline needs one period (last point = first + period)")
        xs = np.linspace(outline[0, 0], outline[-1, 0], 8 * samples + 1)
        g = _envelope(outline, np.asarray(shape, dtype=float), xs, period)
        seg = np.hypot(np.diff(xs), np.diff(g))
        arc = np.concatenate([[0.0], np.cumsum(seg)])
        u = np.linspace(0.0, arc[-1], samples + 1)
        x = np.interp(u, arc, xs)
        y = np.interp(u, arc, g)
        # Tangents by central differences over the periodic samples.
        xe = np.concatenate([[x[-2] - period], x, [x[1] + period]])
        ye = np.concatenate([[y[-2]], y, [y[1]]])
        angle = np.unwrap(np.arctan2(ye[2:] - ye[:-2], xe[2:] - xe[:-2]))
        # A concave corner's bend spread over ``bend`` mm of arc, so that a tip pushed into
        # it finds the normal that takes its force within a few slide steps.
        n = max(1, round(bend / (arc[-1] / samples)))
        if n > 1:
            ring = np.concatenate([angle[-n - 1 : -1], angle, angle[1 : n + 1]])
            angle = np.convolve(ring, np.ones(n) / n, mode="same")[n:-n]
        return cls(period, float(arc[-1]), x, y, angle)


@dataclass(frozen=True)
class PathTable:
    """Several :class:`TipPath` with the same number of samples, stacked for batches.

    Attributes:
        pitch, length: (P,) mm. x, y, angle: (P, m + 1).
    """

    pitch: np.ndarray
    length: np.ndarray
    x: np.ndarray
    y: np.ndarray
    angle: np.ndarray

    @classmethod
    def of(cls, paths) -> PathTable:
        paths = list(paths)
        stack = lambda n: np.stack([np.asarray(getattr(p, n), dtype=float) for p in paths])  # noqa: E731
        return cls(stack("pitch"), stack("length"), stack("x"), stack("y"), stack("angle"))

    def frame(self, which, u):
        """Centre (..., 2), unit tangent (..., 2) and outward normal (..., 2) at arc length
        ``u`` (mm) on the paths ``which`` (integer array broadcasting with u)."""
        m = self.x.shape[1] - 1
        length = self.length[which]
        turns = np.floor(u / length)
        k = (u - turns * length) / length * m
        i = np.clip(np.floor(k).astype(int), 0, m - 1)
        w = k - i
        lerp = lambda a: a[which, i] * (1.0 - w) + a[which, i + 1] * w  # noqa: E731
        a0, a1 = self.angle[which, i], self.angle[which, i + 1]
        a = a0 + w * ((a1 - a0 + np.pi) % (2 * np.pi) - np.pi)
        cos, sin = np.cos(a), np.sin(a)
        out = np.empty((3, *a.shape, 2))
        out[0, ..., 0] = lerp(self.x) + turns * self.pitch[which]
        out[0, ..., 1] = lerp(self.y)
        out[1, ..., 0], out[1, ..., 1] = cos, sin
        out[2, ..., 0], out[2, ..., 1] = -sin, cos
        return out[0], out[1], out[2]

    def derivatives(self, which, u):
        """d(centre)/du (..., 2) and the curvature d(angle)/du (1/mm) at arc length ``u``
        (mm), as :meth:`frame` interpolates them: the centre linearly (its derivative the
        sample interval's chord) and the angle linearly (its curvature constant over each
        interval)."""
        m = self.x.shape[1] - 1
        length = self.length[which]
        k = (u / length - np.floor(u / length)) * m
        i = np.clip(np.floor(k).astype(int), 0, m - 1)
        a0, a1 = self.angle[which, i], self.angle[which, i + 1]
        h = length / m
        chord = np.stack(
            [self.x[which, i + 1] - self.x[which, i], self.y[which, i + 1] - self.y[which, i]],
            -1,
        )
        return chord / h[..., None], ((a1 - a0 + np.pi) % (2 * np.pi) - np.pi) / h

    def _per_path(self, which, x, table):
        """Interpolate ``table(path) -> (xs, values)`` at ``x`` on the paths ``which``,
        one period's x folded in; returns (values, whole periods)."""
        which, x = np.broadcast_arrays(np.asarray(which), np.asarray(x, dtype=float))
        pitch = self.pitch[which]
        turns = np.floor((x - self.x[which, 0]) / pitch)
        xr = x - turns * pitch
        out = np.empty(x.shape)
        for k in np.unique(which):
            sel = which == k
            xs, values = table(k)
            out[sel] = np.interp(xr[sel], xs, values)
        return out, turns

    def arc_at(self, which, x):
        """Arc length u (mm) where the paths ``which`` (integer array) reach ``x`` (mm)."""
        m = self.x.shape[1] - 1
        frac, turns = self._per_path(which, x, lambda k: (self.x[k], np.arange(m + 1) / m))
        return (turns + frac) * self.length[np.asarray(which)]

    def height_at(self, which, x):
        """The path's height (mm) at ``x`` (mm): where a tip there touches."""
        y, _ = self._per_path(which, x, lambda k: (self.x[k], self.y[k]))
        return y
