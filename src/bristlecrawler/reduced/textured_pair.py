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


def _cells(b: PairBatch, x: np.ndarray):
    """Cell ahead and behind of tips at ``x`` (B, 2) and the edges ahead and behind, mm."""
    n = b.fp.shape[-1]
    c = (b.pitch / n)[:, None]
    u = (x - b.origin[:, None]) / c
    fl, ce = np.floor(u + 1e-9), np.ceil(u - 1e-9)
    ahead, behind = fl.astype(int) % n, (ce.astype(int) - 1) % n
    return ahead, behind, b.origin[:, None] + c * (fl + 1.0), b.origin[:, None] + c * (ce - 1.0)


def _resistances(b: PairBatch, x: np.ndarray):
    ahead, behind, up, down = _cells(b, x)
    fp = np.take_along_axis(b.fp, ahead[..., None], axis=2)[..., 0]
    fn = np.take_along_axis(b.fn, behind[..., None], axis=2)[..., 0]
    if b.walls.any():  # a tip on a wall's edge goes no further back
        n = b.fp.shape[-1]
        u = (x - b.origin[:, None]) / (b.pitch / n)[:, None]
        near = np.round(u)
        on = np.take_along_axis(b.walls, (near.astype(int) % n)[..., None], axis=2)[..., 0]
        fn = np.where(on & (np.abs(u - near) < 1e-9), np.inf, fn)
    return fp, fn, up, down


def pair_cycles(b: PairBatch, cycles: int = 2, max_events: int = 200_000):
    """Advance of the front attachment (mm) and actuator work (mJ) of each cycle, each of
    shape (B, cycles), for the breathing stroke 0 -> s_max -> 0 repeated ``cycles`` times."""
    B = b.pitch.size
    K = b.k[:, 0] * b.k[:, 1] / b.k.sum(axis=1)
    L = b.length
    x = np.stack([b.start, b.start + L], axis=1) + b.offset
    s, f, W = np.zeros(B), np.zeros(B), np.zeros(B)
    half = np.zeros(B, dtype=int)
    adv = np.zeros((B, cycles))
    work = np.zeros((B, cycles))
    front0 = _front(b, x, K, L)
    W0 = np.zeros(B)
    tol = 1e-12 * (1.0 + b.length)
    ftol = 1e-12 * (1.0 + np.abs(b.fp).max())
    rows = np.arange(B)
    for _ in range(max_events):
        live = half < 2 * cycles
        if not live.any():
            return adv, work
        fp, fn, up, down = _resistances(b, x)
        hi = np.minimum(fp[:, 0], fn[:, 1])  # rear forwards / front backwards
        lo = np.maximum(-fn[:, 0], -fp[:, 1])  # rear backwards / front forwards
        rear_hi = fp[:, 0] <= fn[:, 1]
        rear_lo = fn[:, 0] <= fp[:, 1]
        rising = half % 2 == 0
        snap_hi, snap_lo = live & (f > hi + ftol), live & (f < lo - ftol)
        # A snap: the weaker tip slides on at frozen s until f is down to its cell's
        # resistance or it reaches the next edge.
        tip = np.where(snap_hi, np.where(rear_hi, 0, 1), np.where(rear_lo, 0, 1))
        fwd = np.where(snap_hi, rear_hi, ~rear_lo)  # the moving tip goes forwards
        edge = np.where(fwd, up[rows, tip], down[rows, tip])
        to_edge = np.abs(edge - x[rows, tip])
        thr = np.where(snap_hi, hi, lo)
        need = np.abs(f - thr) / K
        snap = snap_hi | snap_lo
        d = np.where(need < to_edge, need, to_edge)
        at_edge = need >= to_edge
        f = np.where(snap, np.where(snap_hi, f - K * d, f + K * d), f)
        moved = np.where(at_edge, edge, x[rows, tip] + np.where(fwd, d, -d))
        x[rows, tip] = np.where(snap, moved, x[rows, tip])
        f = np.where(snap & ~at_edge, thr, f)
        # Otherwise the stroke moves on: elastic until a tip yields, or a tip slides.
        go = live & ~snap
        target = np.where(rising, b.s_max, 0.0)
        left = np.abs(target - s)
        at_yield = np.where(rising, f >= hi - ftol, f <= lo + ftol)
        elastic = go & ~at_yield
        de = np.minimum(np.where(rising, hi - f, f - lo) / K, left)
        sgn = np.where(rising, 1.0, -1.0)
        W = W + np.where(elastic, sgn * (f + sgn * 0.5 * K * de) * de, 0.0)
        f_el = np.where(de >= left, f + sgn * K * de, np.where(rising, hi, lo))
        f = np.where(elastic, f_el, f)
        slide = go & at_yield
        tip = np.where(rising, np.where(rear_hi, 0, 1), np.where(rear_lo, 0, 1))
        fwd = np.where(rising, rear_hi, ~rear_lo)
        edge = np.where(fwd, up[rows, tip], down[rows, tip])
        to_edge = np.abs(edge - x[rows, tip])
        ds = np.minimum(to_edge, left)
        W = W + np.where(slide, sgn * f * ds, 0.0)
        moved = np.where(to_edge <= left, edge, x[rows, tip] + np.where(fwd, ds, -ds))
        x[rows, tip] = np.where(slide, moved, x[rows, tip])
        step = np.where(elastic, de, np.where(slide, ds, 0.0))
        s = s + sgn * step
        done = go & (np.abs(target - s) <= tol) & (np.where(elastic, de >= left, ds >= left))
        s = np.where(done, target, s)
        ended = done & ~rising
        if ended.any():
            c = half[ended] // 2
            fr = _front(b, x, K, L)
            adv[ended, c] = fr[ended] - front0[ended]
            work[ended, c] = W[ended] - W0[ended]
            front0 = np.where(ended, fr, front0)
            W0 = np.where(ended, W, W0)
        half = half + done
    raise SolverError(f"two-bristle events did not finish within {max_events} events")


def _front(b: PairBatch, x: np.ndarray, K: np.ndarray, L: np.ndarray) -> np.ndarray:
    """Front attachment at s = 0 from the tips' positions (balance of the two springs)."""
    y = x - b.offset
    k0, k1 = b.k[:, 0], b.k[:, 1]
    X0 = (k0 * y[:, 0] + k1 * (y[:, 1] - L)) / (k0 + k1)
    return X0 + L
