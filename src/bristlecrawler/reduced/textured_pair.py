"""Two bristles on a texture, many designs at once: advance and work per cycle, exact.

With two bristles the balance ``k_0 e_0 + k_1 e_1 = 0`` leaves one force,
``f = K (y_1 - y_0 - L + s)`` with ``K = k_0 k_1 / (k_0 + k_1)`` (N, pulling the rear tip
forwards and the front tip backwards; ``y_i`` the tips' positions less their rest offsets).
The motion is rate independent, so a stroke is its sequence of turning points: each half
stroke raises (contraction) or lowers (extension) ``f`` at ``K`` N per mm of shortening
until it reaches the weaker tip's resistance, that tip then slides at constant ``f`` to
its next cell edge, and a tip entering a weaker cell snaps on at frozen ``s`` until ``f``
has fallen to the new resistance. Each design walks through its events, all designs in
lock step (numpy over the batch): the same motion as :func:`.textured.solve_textured`
for a breathing stroke, without sampling the stroke in time.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from bristlecrawler.errors import InputError, SolverError
from bristlecrawler.reduced.texture import TextureLaw


@dataclass(frozen=True)
class PairBatch:
    """Per design (leading axis B): laws of the rear and front bristle as cell tables
    (N, shape (B, n)), pitch (mm), k (N/mm), origin and tip offsets (mm), segment length
    L (mm), peak shortening s_max (mm) and start position (mm)."""

    fp: np.ndarray  # (B, 2, n)
    fn: np.ndarray  # (B, 2, n)
    walls: np.ndarray  # (B, 2, n): a wall at the start of the cell
    pitch: np.ndarray  # (B,)
    k: np.ndarray  # (B, 2)
    origin: np.ndarray  # (B,)
    offset: np.ndarray  # (B, 2)
    length: np.ndarray  # (B,)
    s_max: np.ndarray  # (B,)
    start: np.ndarray  # (B,)

    @classmethod
    def of(cls, laws, length, s_max, start=0.0) -> PairBatch:
        """A batch from one (rear, front) pair of laws per design (or one law for both)
        and per-design (or shared) length, peak shortening and start, mm."""
        pairs = [(p, p) if isinstance(p, TextureLaw) else tuple(p) for p in laws]
        n = {law.n_cells for pair in pairs for law in pair}
        if len(n) != 1:
            raise InputError("every law of a batch needs the same number of cells")
        B = len(pairs)
        for pair in pairs:
            if pair[0].pitch_mm != pair[1].pitch_mm or pair[0].origin_mm != pair[1].origin_mm:
                raise InputError("both bristles of a design must be on the same texture")
        s_max = np.broadcast_to(np.asarray(s_max, float), (B,)).copy()
        length = np.broadcast_to(np.asarray(length, float), (B,)).copy()
        if np.any(s_max <= 0) or np.any(s_max >= length):
            raise InputError("peak shortening must be positive and below the length (mm)")
        return cls(
            fp=np.array([[p.fp_N for p in pair] for pair in pairs]),
            fn=np.array([[p.fn_N for p in pair] for pair in pairs]),
            walls=np.array([[_wall_edges(p) for p in pair] for pair in pairs]),
            pitch=np.array([pair[0].pitch_mm for pair in pairs]),
            k=np.array([[p.k_N_per_mm for p in pair] for pair in pairs]),
            origin=np.array([pair[0].origin_mm for pair in pairs]),
            offset=np.array([[p.tip_offset_mm for p in pair] for pair in pairs]),
            length=length,
            s_max=s_max,
            start=np.broadcast_to(np.asarray(start, float), (B,)).copy(),
        )


def _wall_edges(law: TextureLaw) -> np.ndarray:
    out = np.zeros(law.n_cells, dtype=bool)
    out[np.round(np.asarray(law.walls_mm) / law.cell_mm).astype(int) % law.n_cells] = True
    return out


class _Tables:
    """The batch's laws as flat tables, indexed by (design, tip, cell)."""

    def __init__(self, b: PairBatch):
        self.n = b.fp.shape[-1]
        self.fp, self.fn = b.fp.ravel(), b.fn.ravel()
        self.walls = b.walls.ravel() if b.walls.any() else None
        self.cell = b.pitch / self.n
        self.origin = b.origin

    def at(self, rows: np.ndarray, x: np.ndarray):
        """Resistances ahead (F_p) and behind (F_n) of tips at ``x`` (rows of the batch,
        shape (R, 2)) and the cell edges ahead and behind, mm."""
        n, c, o = self.n, self.cell[rows, None], self.origin[rows, None]
        u = (x - o) / c
        fl, ce = np.floor(u + 1e-9), np.ceil(u - 1e-9)
        base = (rows[:, None] * 2 + np.arange(2)) * n
        fp = self.fp[base + fl.astype(int) % n]
        fn = self.fn[base + (ce.astype(int) - 1) % n]
        if self.walls is not None:  # a tip on a wall's edge goes no further back
            near = np.round(u)
            on = self.walls[base + near.astype(int) % n] & (np.abs(u - near) < 1e-9)
            fn = np.where(on, np.inf, fn)
        return fp, fn, o + c * (fl + 1.0), o + c * (ce - 1.0)


def _step(tables, rows, x, f, s, W, half, K, s_max, ftol):
    """One event of every live design: a snap, or elastic loading and/or a slide.
    Returns the new x, f, s, W and which designs finished their half stroke."""
    r = np.arange(rows.size)
    fp, fn, up, down = tables.at(rows, x)
    hi = np.minimum(fp[:, 0], fn[:, 1])  # rear forwards / front backwards
    lo = np.maximum(-fn[:, 0], -fp[:, 1])  # rear backwards / front forwards
    rear_hi, rear_lo = fp[:, 0] <= fn[:, 1], fn[:, 0] <= fp[:, 1]
    rising = half % 2 == 0
    sgn = np.where(rising, 1.0, -1.0)
    left = np.where(rising, s_max - s, s)  # stroke left in this half cycle, mm
    # 1. A snap: the weaker tip at the bound f exceeds slides on at frozen s until f is
    # down to its cell's resistance or the tip reaches the next edge.
    snap_hi, snap_lo = f > hi + ftol, f < lo - ftol
    snap = snap_hi | snap_lo
    tip = np.where(snap_hi, ~rear_hi, ~rear_lo).astype(int)
    fwd = np.where(snap_hi, rear_hi, ~rear_lo)
    xt = x[r, tip]
    edge = np.where(fwd, up[r, tip], down[r, tip])
    to_edge = np.abs(edge - xt)
    bound = np.where(snap_hi, hi, lo)
    need = np.abs(f - bound) / K
    d = np.minimum(need, to_edge)
    inside = need < to_edge
    x[r, tip] = np.where(snap, np.where(inside, xt + np.where(fwd, d, -d), edge), xt)
    f = np.where(snap, np.where(inside, bound, f - np.where(snap_hi, K, -K) * d), f)
    # Ended inside its cell at the bound the stroke pushes on: it slides on below.
    settled = snap & inside & (snap_hi == rising)
    # 2. Elastic loading: f moves at K per mm of stroke until a bound or the stroke end.
    bound = np.where(rising, hi, lo)
    elastic = ~snap & np.where(rising, f < hi - ftol, f > lo + ftol)
    de = np.minimum(np.abs(bound - f) / K, left)
    W = W + np.where(elastic, sgn * (f + sgn * 0.5 * K * de) * de, 0.0)
    reached = elastic & (de < left)
    f = np.where(elastic, np.where(reached, bound, f + sgn * K * de), f)
    left = np.where(elastic, left - de, left)
    # 3. A slide at constant f of the weaker tip at that bound, to its next cell edge
    # or the stroke's end (no tip has changed cell since the resistances were read).
    slide = (~snap & ~elastic) | reached | settled
    tip = np.where(rising, ~rear_hi, ~rear_lo).astype(int)
    fwd = np.where(rising, rear_hi, ~rear_lo)
    xt = x[r, tip]
    edge = np.where(fwd, up[r, tip], down[r, tip])
    to_edge = np.abs(edge - xt)
    d = np.minimum(to_edge, left)
    x[r, tip] = np.where(slide, np.where(to_edge <= left, edge, xt + np.where(fwd, d, -d)), xt)
    W = W + np.where(slide, sgn * f * d, 0.0)
    left = np.where(slide, left - d, left)
    done = (~snap | settled) & (left <= 0.0)
    s = np.where(rising, s_max - left, left)
    return x, f, s, W, done


def pair_cycles(b: PairBatch, cycles: int = 2, max_events: int = 200_000):
    """Advance of the front attachment (mm) and actuator work (mJ) of each cycle, each of
    shape (B, cycles), for the breathing stroke 0 -> s_max -> 0 repeated ``cycles`` times."""
    B = b.pitch.size
    tables = _Tables(b)
    K_all = b.k[:, 0] * b.k[:, 1] / b.k.sum(axis=1)
    x_all = np.stack([b.start, b.start + b.length], axis=1) + b.offset
    adv, work = np.zeros((B, cycles)), np.zeros((B, cycles))
    front0 = _front(b, np.arange(B), x_all)
    rows = np.arange(B)
    x, K, s_max = x_all.copy(), K_all, b.s_max
    s, f, W, W0 = np.zeros(B), np.zeros(B), np.zeros(B), np.zeros(B)
    half = np.zeros(B, dtype=int)
    ftol = 1e-12 * (1.0 + np.abs(b.fp).max())
    for _ in range(max_events):
        if rows.size == 0:
            return adv, work
        rising = half % 2 == 0
        x, f, s, W, done = _step(tables, rows, x, f, s, W, half, K, s_max, ftol)
        ended = done & ~rising
        if ended.any():
            g, c = rows[ended], half[ended] // 2
            fr = _front(b, g, x[ended])
            adv[g, c] = fr - front0[g]
            work[g, c] = W[ended] - W0[g]
            front0[g], W0[g] = fr, W[ended]
        half = half + done
        keep = half < 2 * cycles
        if not keep.all():
            rows, x, K, s_max = rows[keep], x[keep], K[keep], s_max[keep]
            s, f, W, half = s[keep], f[keep], W[keep], half[keep]
    raise SolverError(f"two-bristle events did not finish within {max_events} events")


def _front(b: PairBatch, rows: np.ndarray, x: np.ndarray) -> np.ndarray:
    """Front attachment at s = 0 from the tips' positions (balance of the two springs)."""
    y = x - b.offset[rows]
    k0, k1, L = b.k[rows, 0], b.k[rows, 1], b.length[rows]
    X0 = (k0 * y[:, 0] + k1 * (y[:, 1] - L)) / (k0 + k1)
    return X0 + L
