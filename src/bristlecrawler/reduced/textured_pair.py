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
from bristlecrawler.results.texture import TextureLaw


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
    """The batch's laws as flat tables, indexed by (design, tip, cell).

    F_n is stored shifted by one cell with the last cell in front (``n + 1`` entries per
    tip), so that the cell behind a tip is read at the index of the cell ahead plus 0 (on
    an edge) or 1 (inside a cell): one reduction modulo ``n`` per tip instead of two.
    """

    def __init__(self, b: PairBatch):
        n = self.n = b.fp.shape[-1]
        self.fp = b.fp.ravel()
        self.fn = np.concatenate([b.fn[..., -1:], b.fn], axis=-1).ravel()
        self.walls = b.walls.ravel() if b.walls.any() else None
        # A bit mask reduces modulo a power of two, also below zero, at a fraction of
        # the cost of an integer remainder.
        self.mask = n - 1 if n & (n - 1) == 0 else None

    def at(self, st: _State):
        """Resistances ahead (F_p) and behind (F_n) of the tips of the live designs, and
        the floor and ceiling of their positions in cells, each shape (2, R): rear tips,
        front tips. The cell edges ahead and behind are at ``fl + 1`` and ``ce - 1``."""
        u = (st.x - st.origin) / st.cell
        fl, ce = np.floor(u + 1e-9), np.ceil(u - 1e-9)
        ahead = fl.astype(np.int64)
        if self.mask is None:
            ahead %= self.n
        else:
            ahead &= self.mask
        # ceil(u - 1e-9) - floor(u + 1e-9) is 0 on an edge and 1 inside a cell.
        behind = ahead + st.fn_base
        behind += ce > fl
        ahead += st.fp_base
        fp, fn = self.fp[ahead], self.fn[behind]
        if self.walls is not None:  # a tip on a wall's edge goes no further back
            # (on an edge, the edge is floor(u + 1e-9): the index of the cell ahead)
            on = self.walls[ahead] & (np.abs(u - np.round(u)) < 1e-9)
            fn[on] = np.inf
        return fp, fn, fl, ce


class _State:
    """The live designs of a batch: tips' positions x (2, R: rear, front), force f,
    shortening s, work W, half strokes done, and per-design constants."""

    def __init__(self, b: PairBatch, x: np.ndarray):
        B, n = b.fp.shape[0], b.fp.shape[-1]
        self.rows = np.arange(B)
        tips = np.stack([2 * self.rows, 2 * self.rows + 1])  # (2, B)
        self.fp_base, self.fn_base = tips * n, tips * (n + 1)
        self.x = np.ascontiguousarray(x.T)
        self.cell = b.pitch / n
        self.origin = b.origin.copy()
        self.K = b.k[:, 0] * b.k[:, 1] / b.k.sum(axis=1)
        self.s_max = b.s_max.copy()
        self.s, self.f, self.W = np.zeros(B), np.zeros(B), np.zeros(B)
        self.half = np.zeros(B, dtype=np.int64)

    def keep(self, keep: np.ndarray) -> None:
        for name in ("rows", "cell", "origin", "K", "s_max", "s", "f", "W", "half"):
            setattr(self, name, getattr(self, name)[keep])
        for name in ("x", "fp_base", "fn_base"):
            setattr(self, name, getattr(self, name)[:, keep])


def _step(tables: _Tables, st: _State, ftol: float) -> np.ndarray:
    """One event of every live design: a snap, or elastic loading and/or a slide.
    Updates ``st`` and returns which designs finished their half stroke.

    Every event moves at most one tip, the weaker at the bound f is at or pushed
    towards: at the upper bound (f pulls the rear tip forwards and the front tip
    backwards) the rear tip forwards or the front tip backwards, at the lower bound the
    reverse. A snap goes to the bound f exceeds, loading and sliding to the bound the
    stroke pushes f to; a snap that settles at the latter slides on in the same event.
    """
    fp, fn, fl, ce = tables.at(st)
    x, f, K = st.x, st.f, st.K
    hi = np.minimum(fp[0], fn[1])
    lo = -np.minimum(fn[0], fp[1])
    rising = (st.half & 1) == 0
    left = np.where(rising, st.s_max - st.s, st.s)  # stroke left in this half cycle, mm
    snap_hi, snap_lo = f > hi + ftol, f < lo - ftol
    snap = snap_hi | snap_lo
    upper = snap_hi | (rising & ~snap_lo)  # the bound of this event is the upper one
    sgn = np.where(upper, 1.0, -1.0)  # the stroke's sign where the stroke moves f or a tip
    bound = np.where(upper, hi, lo)
    # The moving tip: the front one where it is the weaker at the bound.
    tip = np.where(upper, fp[0] > fn[1], fn[0] > fp[1])
    fwd = tip ^ upper
    step = np.where(fwd, 1.0, -1.0)
    xt = np.where(tip, x[1], x[0])
    cells = np.where(fwd, np.where(tip, fl[1], fl[0]) + 1.0, np.where(tip, ce[1], ce[0]) - 1.0)
    edge = st.origin + st.cell * cells
    reach = np.abs(bound - f) / K  # tip travel of a snap, stroke of a loading, mm
    # 1. A snap: the tip slides on at frozen s until f is down to the bound or the tip
    # reaches its cell's edge.
    to_edge = np.abs(edge - xt)
    inside = reach < to_edge
    xt = np.where(snap, np.where(inside, xt + step * np.minimum(reach, to_edge), edge), xt)
    # 2. Elastic loading: f moves at K per mm of stroke until the bound or the stroke end.
    elastic = ~snap & (sgn * f < sgn * bound - ftol)
    de = np.where(elastic, np.minimum(reach, left), 0.0)
    reached = elastic & (de < left)
    W = st.W + sgn * (f + sgn * 0.5 * K * de) * de
    moved = np.where(snap, -np.minimum(reach, to_edge), de)
    f = np.where((snap & inside) | reached, bound, f + sgn * K * moved)
    left = left - de
    # 3. A slide at constant f of the tip to its cell's edge or the stroke's end (no
    # tip has changed cell since the resistances were read). A snap that ended inside
    # its cell at the bound the stroke pushes on slides on below.
    settled = snap & inside & (upper == rising)
    slide = (~snap & ~elastic) | reached | settled
    to_edge = np.abs(edge - xt)
    d = np.where(slide, np.minimum(to_edge, left), 0.0)
    xt = np.where(slide & (to_edge <= left), edge, xt + step * d)
    x[0] = np.where(tip, x[0], xt)
    x[1] = np.where(tip, xt, x[1])
    st.W = W + sgn * f * d
    left = left - d
    st.f = f
    st.s = np.where(rising, st.s_max - left, left)
    return (~snap | settled) & (left <= 0.0)


def pair_cycles(b: PairBatch, cycles: int = 2, max_events: int = 200_000):
    """Advance of the front attachment (mm) and actuator work (mJ) of each cycle, each of
    shape (B, cycles), for the breathing stroke 0 -> s_max -> 0 repeated ``cycles`` times."""
    B = b.pitch.size
    tables = _Tables(b)
    x_all = np.stack([b.start, b.start + b.length], axis=1) + b.offset
    adv, work = np.zeros((B, cycles)), np.zeros((B, cycles))
    front0 = _front(b, np.arange(B), x_all)
    W0 = np.zeros(B)
    st = _State(b, x_all)
    ftol = 1e-12 * (1.0 + np.abs(b.fp).max())
    last = 2 * cycles
    for _ in range(max_events):
        if st.rows.size == 0:
            return adv, work
        done = _step(tables, st, ftol)
        done &= st.half < last  # designs past their last cycle step on until dropped
        ended = done & ((st.half & 1) == 1)
        if ended.any():
            g, c = st.rows[ended], st.half[ended] // 2
            fr = _front(b, g, st.x[:, ended].T)
            adv[g, c] = fr - front0[g]
            work[g, c] = st.W[ended] - W0[g]
            front0[g], W0[g] = fr, st.W[ended]
        st.half += done
        # Dropping finished designs copies every array, so it waits until they are a
        # sixteenth of the live ones; until then they step on, their results recorded.
        finished = int(np.count_nonzero(st.half >= last))
        if finished and 16 * finished >= st.rows.size:
            st.keep(st.half < last)
    raise SolverError(f"two-bristle events did not finish within {max_events} events")


def _front(b: PairBatch, rows: np.ndarray, x: np.ndarray) -> np.ndarray:
    """Front attachment at s = 0 from the tips' positions (balance of the two springs)."""
    y = x - b.offset[rows]
    k0, k1, L = b.k[rows, 0], b.k[rows, 1], b.length[rows]
    X0 = (k0 * y[:, 0] + k1 * (y[:, 1] - L)) / (k0 + k1)
    return X0 + L
