"""A bristle on a periodic texture: its resistance as a force law over the tip's position.

The paper's law (eq. 4.1) gives one tip one resistance per direction, F_p and F_n. On a
grooved substrate the resistance depends on where the tip is within a groove pitch: it
ripples along the grain, and against the grain it rises at a groove wall far above what
the other bristles can pull, so that a tip sliding back stops there (it locks). The
texture law is the paper's law with position-dependent thresholds,

    tip slides forwards only at   k e = F_p(x)   (the cell ahead of the tip),
    tip slides backwards only at  k e = -F_n(x)  (the cell behind the tip),

piecewise constant over ``n`` equal cells of one pitch, periodic, F_n = inf where a tip
locks. It is the rate-independent limit of a bristle on a wiggly potential (a
Prandtl-Tomlinson system, Gidoni & DeSimone, arXiv 1602.05611): where the threshold falls
ahead of a sliding tip faster than its spring can follow, the tip snaps to the next
position that holds it. A constant law (one cell) is the paper's law.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from bristlecrawler.errors import InputError, positive
from bristlecrawler.results.keys import FN_N, FP_N, K_N_PER_MM


def _cells(name: str, values, n: int | None = None, allow_inf: bool = False) -> np.ndarray:
    arr = np.atleast_1d(np.asarray(values, dtype=float))
    if arr.ndim != 1 or arr.size < 1 or (n is not None and arr.size != n):
        raise InputError(f"{name} must be one value per cell ({n or 'at least one'} cells)")
    ok = (arr > 0) & (np.isfinite(arr) | (allow_inf & (arr == np.inf)))
    if not ok.all():
        raise InputError(f"{name} must be positive and finite per cell, got {arr.tolist()}")
    arr = arr.copy()
    arr.setflags(write=False)
    return arr


@dataclass(frozen=True)
class TextureLaw:
    """Resistance of one bristle tip over one pitch of a periodic texture.

    Attributes:
        pitch_mm: period of the texture, mm.
        fp_N: resistance to sliding forwards (along the grain), N, one value per cell of
            ``pitch_mm / n``; cell j covers ``origin_mm + [j, j + 1) * pitch_mm / n``
            (mod pitch). Finite, > 0.
        fn_N: resistance to sliding backwards (against the grain), N, per cell; ``inf``
            where a tip locks against a wall.
        k_N_per_mm: stiffness of the bristle between its attachment and its tip, N/mm.
        origin_mm: substrate coordinate where cell 0 starts, mm.
        tip_offset_mm: the tip's position relative to its attachment at rest, mm (where a
            tip starts on the substrate).
        walls_mm: positions within a pitch (mm from ``origin_mm``, on cell edges) of walls
            of no width that no tip crosses backwards (a groove's wall).
    """

    pitch_mm: float
    fp_N: np.ndarray
    fn_N: np.ndarray
    k_N_per_mm: float
    origin_mm: float = 0.0
    tip_offset_mm: float = 0.0
    walls_mm: tuple[float, ...] = ()

    def __post_init__(self) -> None:
        object.__setattr__(self, "pitch_mm", positive("texture pitch (mm)", self.pitch_mm))
        object.__setattr__(self, "k_N_per_mm", positive("k (N/mm)", self.k_N_per_mm))
        fp = _cells("F_p(x) (N)", self.fp_N)
        object.__setattr__(self, "fp_N", fp)
        object.__setattr__(self, "fn_N", _cells("F_n(x) (N)", self.fn_N, fp.size, True))
        for name in ("origin_mm", "tip_offset_mm"):
            v = float(getattr(self, name))
            if not np.isfinite(v):
                raise InputError(f"texture {name} must be finite, got {v}")
            object.__setattr__(self, name, v)
        walls = np.asarray(self.walls_mm, dtype=float).ravel() % self.pitch_mm
        u = walls / self.cell_mm
        if np.any(np.abs(u - np.round(u)) > 1e-9):
            raise InputError(f"walls must lie on cell edges ({self.cell_mm:g} mm apart)")
        edges = np.round(u).astype(int) % self.n_cells
        object.__setattr__(
            self, "walls_mm", tuple(float(v) for v in np.unique(edges) * self.cell_mm)
        )

    @classmethod
    def constant(cls, fp: float, fn: float, k: float, pitch: float = 1.0) -> TextureLaw:
        """The paper's law (eq. 4.1) as a texture law: one cell, F_p and F_n everywhere."""
        return cls(pitch_mm=pitch, fp_N=[fp], fn_N=[fn], k_N_per_mm=k)

    @classmethod
    def sawtooth(
        cls, pitch: float, fp: float, k: float, cells: int = 1, fn: float | None = None
    ) -> TextureLaw:
        """A ratchet: F_p and F_n (default F_p / 2) everywhere, and a wall at the start of
        each pitch: a tip pulled back slides to the wall behind it."""
        fn = np.full(cells, 0.5 * fp if fn is None else fn)
        return cls(pitch, np.full(cells, fp), fn, k, walls_mm=(0.0,))

    @property
    def n_cells(self) -> int:
        return int(self.fp_N.size)

    @property
    def cell_mm(self) -> float:
        """Width of one cell, mm."""
        return self.pitch_mm / self.n_cells

    @property
    def is_constant(self) -> bool:
        """True when the law is the same at every position (the paper's law)."""
        same = np.all(self.fp_N == self.fp_N[0]) and np.all(self.fn_N == self.fn_N[0])
        return bool(same and not self.walls_mm)

    @property
    def lock_positions_mm(self) -> np.ndarray:
        """Positions within a pitch (mm from ``origin_mm``) where a tip sliding backwards
        stops against a wall whatever the other bristles pull, as long as they slide
        forwards on the same law: the forward edges of the cells whose F_n exceeds every
        F_p (or is infinite), where such a cell follows one that does not."""
        wall = self.fn_N > self.fp_N.max()
        start = wall & ~np.roll(wall, -1)
        edges = ((np.flatnonzero(start) + 1) % self.n_cells) * self.cell_mm
        return np.unique(np.concatenate([edges, self.walls_mm]))

    @property
    def mean_fp_N(self) -> float:
        """Mean resistance along the grain over a pitch, N (the paper's F_p of this law)."""
        return float(self.fp_N.mean())

    def cell_ahead(self, x: np.ndarray) -> np.ndarray:
        """Index of the cell a tip at ``x`` (mm) enters moving forwards."""
        u = (np.asarray(x, dtype=float) - self.origin_mm) / self.cell_mm
        return np.floor(u + 1e-9).astype(int) % self.n_cells

    def cell_behind(self, x: np.ndarray) -> np.ndarray:
        """Index of the cell a tip at ``x`` (mm) enters moving backwards."""
        u = (np.asarray(x, dtype=float) - self.origin_mm) / self.cell_mm
        return (np.ceil(u - 1e-9).astype(int) - 1) % self.n_cells

    def forward_resistance(self, x) -> np.ndarray:
        """F_p at tip positions ``x`` (mm), N."""
        return self.fp_N[self.cell_ahead(x)]

    def backward_resistance(self, x) -> np.ndarray:
        """F_n at tip positions ``x`` (mm), N (inf at a wall)."""
        fn = self.fn_N[self.cell_behind(x)]
        if not self.walls_mm:
            return fn
        u = (np.asarray(x, dtype=float) - self.origin_mm) / self.cell_mm
        near = np.round(u)
        edge = near.astype(int) % self.n_cells
        walls = np.zeros(self.n_cells, dtype=bool)
        walls[np.round(np.asarray(self.walls_mm) / self.cell_mm).astype(int)] = True
        return np.where((np.abs(u - near) < 1e-9) & walls[edge], np.inf, fn)

    def next_edge(self, x, direction: np.ndarray) -> np.ndarray:
        """The nearest cell edge strictly ahead of ``x`` (mm) in ``direction`` (+1/-1)
        where the law changes; +-inf for a constant law."""
        x = np.asarray(x, dtype=float)
        d = np.asarray(direction)
        if self.is_constant:
            return np.where(d > 0, np.inf, -np.inf)
        c = self.cell_mm
        u = (x - self.origin_mm) / c
        up = np.floor(u + 1e-9) + 1.0
        down = np.ceil(u - 1e-9) - 1.0
        return self.origin_mm + c * np.where(d > 0, up, down)

    def to_dict(self) -> dict:
        """The law with units in the keys (JSON-ready; a wall's F_n is the string "inf")."""
        return {
            "pitch_mm": self.pitch_mm,
            "cell_mm": self.cell_mm,
            "origin_mm": self.origin_mm,
            "tip_offset_mm": self.tip_offset_mm,
            K_N_PER_MM: self.k_N_per_mm,
            FP_N: self.fp_N.tolist(),
            FN_N: [v if np.isfinite(v) else "inf" for v in self.fn_N.tolist()],
            "walls_mm": list(self.walls_mm),
            "lock_positions_mm": self.lock_positions_mm.tolist(),
        }

    @classmethod
    def from_dict(cls, d: dict) -> TextureLaw:
        """Inverse of :meth:`to_dict`."""
        try:
            fn = [np.inf if v == "inf" else float(v) for v in d[FN_N]]
            return cls(
                pitch_mm=d["pitch_mm"],
                fp_N=d[FP_N],
                fn_N=fn,
                k_N_per_mm=d[K_N_PER_MM],
                origin_mm=d.get("origin_mm", 0.0),
                tip_offset_mm=d.get("tip_offset_mm", 0.0),
                walls_mm=tuple(d.get("walls_mm", ())),
            )
        except (KeyError, TypeError, ValueError) as err:
            raise InputError(f"not a texture law: {err}") from None
