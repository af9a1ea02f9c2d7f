"""One tip dragged over a texture: the quasi-static stick, slip and snaps of a tip on its
path (:class:`.path.TipPath`) under a dead normal load, pulled along by a linear spring
(the bristle's compliance along the substrate), and the friction law it adds up to.

The tip carries a dead load W (N, downwards) and is pulled by a spring of stiffness k
(N/mm) whose far end, the base, moves by x_b along the substrate. With the tip at a point
of its path whose tangent makes the angle a with the direction of the drag, the tip sticks
while the spring's force F = k (x_b - x_tip) is below

    F_req(a) = W (sin a + mu cos a) / (cos a - mu sin a)        (cos a > mu sin a),

and cannot be moved at all where cos a <= mu sin a (the tip locks). A tip that moves goes
to the first point ahead of it where it can stick again with the base where it is (a
snap's first stop, as in the crawler's slide corrector), so the tip's place as the base
moves on is the first point of the path whose release position x + F_req / k is beyond the
base. The mean force over whole periods is the energy dissipated per mm of drag: the
texture's friction law in that direction.

Small-pitch limit (Gidoni & DeSimone, "On the genesis of directional friction through
bristle-like mediating elements", arXiv 1602.05611): shrinking the period with the facets'
slopes fixed, the spring's stretch varies over a period by no more than k times a
period's length, so the mean force tends to the largest F_req over a period, the
resistance of the steepest facet the tip climbs, W tan(theta + arctan mu): a rate-
independent friction law whose coefficient depends on the direction of sliding. Units:
mm, N, mJ, rad.
"""

from __future__ import annotations

import numpy as np

from bristlecrawler.reduced.bristled.path import PathTable, PolylineSurface, TipPath, disc_shape


def sawtooth(pitch: float, rise_deg: float, drop_deg: float) -> PolylineSurface:
    """A sawtooth of period ``pitch`` (mm): a facet rising at ``rise_deg`` towards +x, then
    one falling at ``drop_deg`` back to the base line."""
    tr, td = np.tan(np.radians(rise_deg)), np.tan(np.radians(drop_deg))
    peak = pitch * td / (tr + td)
    height = peak * tr
    return PolylineSurface(((0.0, 0.0), (peak, height), (pitch, 0.0)))


def climbing_resistance(slope_deg, mu: float, load: float):
    """The force along the substrate (N) that slides a point under the dead ``load`` (N) up
    a facet of slope ``slope_deg`` with Coulomb's ``mu``: W (sin + mu cos) / (cos - mu sin),
    infinite where the facet locks."""
    a = np.radians(np.asarray(slope_deg, float))
    den = np.cos(a) - mu * np.sin(a)
    force = load * (np.sin(a) + mu * np.cos(a)) / np.where(den > 0, den, 1.0)
    return np.where(den > 0, force, np.inf)


def tip_path(surface, radius: float, samples: int = 2048) -> TipPath:
    """The path of a disc of ``radius`` (mm) over ``surface``, its concave corners' bends
    as wide as the disc (so that the path scales with the texture)."""
    return TipPath.over(surface.outline(), disc_shape(radius), samples, bend=radius)


def drag_force(
    path: TipPath, mu: float, load: float, stiffness: float, periods: int = 8, backwards=False
) -> float:
    """The mean force (N) of the spring that drags a tip along ``path`` (against the grain
    of x if ``backwards``) over ``periods`` whole periods, after the spring has been
    stretched to the steepest climb's resistance (the transient left out); infinite where
    a facet locks the tip."""
    table = PathTable.of([path])
    m = path.x.size - 1
    one = np.linspace(0.0, path.length, m + 1)
    _, t, _ = table.frame(np.zeros(one.shape, int), one)
    a = np.arctan2(t[:, 1] * (-1.0 if backwards else 1.0), t[:, 0])
    peak = float(np.max(climbing_resistance(np.degrees(a), mu, load)))
    if not np.isfinite(peak):
        return np.inf
    settle = int(np.ceil(peak / stiffness / path.pitch)) + 1
    turns = settle + periods + 1
    u = np.linspace(0.0, turns * path.length, turns * m + 1)
    centre, t, _ = table.frame(np.zeros(u.shape, int), u)
    x, tx, ty = centre[:, 0], t[:, 0], t[:, 1]
    if backwards:
        x, tx, ty = -x[::-1], tx[::-1], -ty[::-1]
    need = climbing_resistance(np.degrees(np.arctan2(ty, tx)), mu, load)
    release = np.maximum.accumulate(x + need / stiffness)
    start = x[0] + settle * path.pitch
    base = np.linspace(start, start + periods * path.pitch, 2000 * periods + 1)
    at = np.minimum(np.searchsorted(release, base, side="right"), x.size - 1)
    force = stiffness * (base - x[at])
    return float(np.trapezoid(force, base) / (base[-1] - base[0]))
