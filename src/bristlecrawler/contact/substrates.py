"""Rigid analytic substrates: flat, rectangular grooves, sawtooth teeth, periodic polyline.

Each substrate is a frozen dataclass registered as a PyTree whose fields are leaves (so one
compiled contact kernel serves every design, and ``jax.vmap`` runs over a batch of designs
built with array-valued fields). ``profile()`` turns the parameters into the common
:class:`~bristlecrawler.contact.profile.PeriodicProfile` with traceable JAX operations, and
:func:`~bristlecrawler.contact.profile.project` does the geometry.

A batch of designs for ``jax.vmap(project, in_axes=(0, None))`` needs every field batched:
``jax.tree.map(lambda *x: jnp.stack(x), *designs)`` stacks designs built one by one (and
checked one by one).

The solid is the region below the profile (y up, mm). Parameters are checked when the
object is built from concrete values; errors are :class:`~bristlecrawler.errors.InputError`
with a one-line message naming the parameter. The paper's substrate (Section 2: "evenly
spaced rectangular symmetric grooves 1 mm wide and 0.25 mm deep") is :data:`PAPER_GROOVES`
with an assumed pitch of 2 mm (the paper does not give the spacing).
"""

from __future__ import annotations

import abc
from typing import Any, ClassVar

import jax
import jax.numpy as jnp
import numpy as np

from bristlecrawler._pytree import as_float_leaf, is_concrete, pytree
from bristlecrawler.contact.profile import PeriodicProfile, check_vertices, convex_corners
from bristlecrawler.errors import InputError
from bristlecrawler.settings import MAX_LENGTH, REQUIRED, setting


def _level(default: Any, doc: str) -> Any:
    """A level or a position along x, mm: any value within +-MAX_LENGTH."""
    return setting(default, doc, ge=-MAX_LENGTH, le=MAX_LENGTH)


def _size(doc: str) -> Any:
    """A positive size with no default, mm."""
    return setting(REQUIRED, doc, gt=0.0, le=MAX_LENGTH)


def _radius(doc: str) -> Any:
    """A fillet radius, mm: 0 keeps the corner sharp."""
    return setting(0.0, doc, ge=0.0, le=MAX_LENGTH)


def _require(ok: np.ndarray | bool, message: str) -> None:
    if not bool(np.all(ok)):
        raise InputError(message)


def _finite(name: str, value: jax.Array) -> np.ndarray:
    v = np.asarray(value, dtype=float)
    _require(np.isfinite(v), f"{name} must be finite, got {v}")
    return v


class Substrate(abc.ABC):
    """What the contact terms, the crawler and the drag tests ask of a rigid substrate.

    A substrate is a PyTree (:func:`~bristlecrawler._pytree.pytree`) whose fields are its
    numbers, checked in ``__post_init__`` where they are concrete, with one hook:
    :meth:`profile`, its boundary over one period as a :class:`PeriodicProfile` built with
    traceable JAX operations. :attr:`period` and :attr:`has_corners` follow from it.
    Its fields are :func:`~bristlecrawler.fe.options.setting` declarations (meaning, unit,
    range), and the class is registered under its scenario ``kind``
    (``class Waves(Substrate, kind="waves")``): the scenario's ``[substrate]`` table of
    that kind is generated from the declarations, and the rules between the fields are
    the constructor's. Adding a substrate is one class here."""

    #: Registered substrates by scenario kind, in the order they were declared.
    kinds: ClassVar[dict[str, type[Substrate]]] = {}
    #: The substrate's name in a scenario (``substrate.kind``).
    kind: ClassVar[str] = ""

    def __init_subclass__(cls, kind: str | None = None, **kwargs) -> None:
        super().__init_subclass__(**kwargs)
        if kind is not None:
            cls.kind = kind
            Substrate.kinds[kind] = cls

    @abc.abstractmethod
    def profile(self) -> PeriodicProfile:
        """The boundary over one period (the solid is below it), mm."""

    @property
    def period(self) -> float:
        """The profile's period, mm (a flat plane: 1 mm, the length the drag tests average
        its sliding forces over)."""
        return float(np.asarray(self.profile().period))

    @property
    def has_corners(self) -> bool:
        """Whether the profile has convex corners (:func:`convex_corners`: the corner
        contact's partners). A flat plane has none."""
        return len(convex_corners(self)[0]) > 0


@pytree()
class Flat(Substrate, kind="flat"):
    """A flat plane, y = height.

    Attributes:
        height: level of the surface, mm.
    """

    height: jax.Array = _level(0.0, "surface level, mm")

    @property
    def has_corners(self) -> bool:
        return False  # a straight line (and no program to build to say so)

    def __post_init__(self) -> None:
        as_float_leaf(self, "height")
        if is_concrete(self.height):
            _finite("height", self.height)

    def profile(self) -> PeriodicProfile:
        # Any period works for a straight line; 1 mm keeps arc length equal to x.
        h = self.height
        zero = jnp.zeros_like(h)
        v = jnp.stack([jnp.stack([zero, h], -1), jnp.stack([zero + 1.0, h], -1)], axis=-2)
        return PeriodicProfile(vertices=v, fillets=jnp.zeros((*v.shape[:-2], 1)))


@pytree()
class Grooves(Substrate, kind="grooves"):
    """Rectangular grooves (the paper's substrate), evenly spaced in a flat land at y = top.

    Groove k spans ``phase + k pitch <= x <= phase + k pitch + width`` with its bottom at
    ``y = top - depth``. The optional fillets round the corners with circular arcs:
    ``fillet_top`` the convex corners where a wall meets the land, ``fillet_bottom`` the
    concave corners where a wall meets the groove bottom; 0 keeps a corner sharp.

    Attributes:
        width: groove width, mm; 0 < width < pitch.
        depth: groove depth, mm; > 0.
        pitch: groove spacing (period), mm; > 0.
        phase: x of the left wall of groove 0, mm.
        top: level of the land between grooves, mm.
        fillet_top: radius of the convex land corners, mm; <= width/2, <= (pitch - width)/2,
            and fillet_top + fillet_bottom <= depth, so both fit on the wall.
        fillet_bottom: radius of the concave bottom corners, mm; <= width/2.
    """

    width: jax.Array = _size("groove width, mm")
    depth: jax.Array = _size("groove depth, mm")
    pitch: jax.Array = _size("groove spacing, mm")
    phase: jax.Array = _level(0.0, "x of a groove's left wall, mm")
    top: jax.Array = _level(0.0, "land level, mm")
    fillet_top: jax.Array = _radius("radius of the convex land corners, mm")
    fillet_bottom: jax.Array = _radius("radius of the concave bottom corners, mm")

    def __post_init__(self) -> None:
        names = ("width", "depth", "pitch", "phase", "top", "fillet_top", "fillet_bottom")
        vals = [as_float_leaf(self, n) for n in names]
        if not is_concrete(*vals):
            return
        w, d, p, _, _, rt, rb = (_finite(n, v) for n, v in zip(names, vals, strict=True))
        for name, x in (("width", w), ("depth", d), ("pitch", p)):
            _require(x > 0, f"groove {name} must be > 0 mm, got {x}")
        _require(w < p, f"groove width ({w} mm) must be smaller than the pitch ({p} mm)")
        for name, r in (("fillet_top", rt), ("fillet_bottom", rb)):
            _require(r >= 0, f"{name} must be >= 0 mm, got {r}")
            _require(r <= 0.5 * w, f"{name} ({r} mm) exceeds half the groove width ({w} mm)")
            _require(r <= d, f"{name} ({r} mm) exceeds the groove depth ({d} mm)")
        _require(
            rt <= 0.5 * (p - w),
            f"fillet_top ({rt} mm) exceeds half the land width pitch - width ({p - w} mm)",
        )
        _require(
            rt + rb <= d,
            f"fillet_top + fillet_bottom ({rt + rb} mm) exceeds the groove depth ({d} mm)",
        )

    def profile(self) -> PeriodicProfile:
        # One period from the middle of a land to the middle of the next, so that no
        # corner sits on the period boundary (the join there is straight).
        w, d, p, ph, top = self.width, self.depth, self.pitch, self.phase, self.top
        x0 = ph - 0.5 * (p - w)
        xy = jnp.broadcast_arrays(
            x0, ph, ph, ph + w, ph + w, x0 + p, top, top, top - d, top - d, top, top
        )
        v = jnp.stack([jnp.stack(xy[:6], -1), jnp.stack(xy[6:], -1)], -1)
        zero = jnp.zeros_like(w)
        rt, rb = self.fillet_top + zero, self.fillet_bottom + zero
        r = jnp.stack(jnp.broadcast_arrays(zero, rt, rb, rb, rt), -1)
        return PeriodicProfile(vertices=v, fillets=r)


@pytree()
class Sawtooth(Substrate, kind="sawtooth"):
    """Asymmetric teeth, for directional substrates.

    From a valley at ``x = phase`` (y = base) the profile rises linearly to the crest
    (y = base + height) over ``rise_fraction * pitch`` and falls back linearly over the rest
    of the pitch. ``rise_fraction`` 1 (or 0) gives a vertical drop (or rise).

    Attributes:
        pitch: tooth spacing, mm; > 0.
        height: crest height above the valleys, mm; > 0.
        rise_fraction: fraction of the pitch spent rising, dimensionless, in [0, 1].
        phase: x of a valley, mm.
        base: level of the valleys, mm.
    """

    pitch: jax.Array = _size("tooth spacing, mm")
    height: jax.Array = _size("tooth height, mm")
    rise_fraction: jax.Array = setting(0.8, "fraction of the pitch rising, -", ge=0.0, le=1.0)
    phase: jax.Array = _level(0.0, "x of a valley, mm")
    base: jax.Array = _level(0.0, "valley level, mm")

    def __post_init__(self) -> None:
        names = ("pitch", "height", "rise_fraction", "phase", "base")
        vals = [as_float_leaf(self, n) for n in names]
        if not is_concrete(*vals):
            return
        p, h, f, _, _ = (_finite(n, v) for n, v in zip(names, vals, strict=True))
        _require(p > 0, f"sawtooth pitch must be > 0 mm, got {p}")
        _require(h > 0, f"sawtooth height must be > 0 mm, got {h}")
        _require((f >= 0) & (f <= 1), f"sawtooth rise_fraction must be in [0, 1], got {f}")

    def profile(self) -> PeriodicProfile:
        p, h, f, ph, b = self.pitch, self.height, self.rise_fraction, self.phase, self.base
        xs = jnp.broadcast_arrays(ph, ph + f * p, ph + p, b, b + h, b)
        v = jnp.stack([jnp.stack(xs[:3], -1), jnp.stack(xs[3:], -1)], -1)
        return PeriodicProfile(vertices=v, fillets=jnp.zeros((*v.shape[:-2], 2)))


@pytree()
class Polyline(Substrate, kind="polyline"):
    """A periodic polyline, given by its points over one period.

    Attributes:
        points: (n + 1, 2) points, mm. The first and last have the same y and their x differ
            by the period; x must not decrease (equal x makes a vertical wall) and the curve
            must not fold back on itself. Corners are sharp.
    """

    points: jax.Array = setting(REQUIRED, "[[x, y], ...] over exactly one period, mm")

    def __post_init__(self) -> None:
        pts = as_float_leaf(self, "points")
        if is_concrete(pts):
            check_vertices(np.asarray(pts), "points")
            far = np.abs(np.asarray(pts)) > MAX_LENGTH
            if np.any(far):
                v = np.asarray(pts)[far][0]
                raise InputError(f"points must be within +-{MAX_LENGTH:g} mm, got {v:g}")

    def profile(self) -> PeriodicProfile:
        pts = self.points
        return PeriodicProfile(
            vertices=pts, fillets=jnp.zeros((*pts.shape[:-2], pts.shape[-2] - 1))
        )


#: Substrate of the paper's experiments and FE model (Section 2); the pitch is assumed.
PAPER_GROOVES = Grooves(width=1.0, depth=0.25, pitch=2.0)
#: Friction coefficient bristle/substrate that matched the experiments (paper, Section 3).
PAPER_MU = 0.65
