"""The reduced crawler on a texture: N bristles, each a spring to a tip with a
:class:`~bristlecrawler.results.texture.TextureLaw`, solved exactly event by event.

The unknowns and balance are the paper's (eqs. 4.3-4.5, see :mod:`.solver`); what changes is
that a tip's yield elongations ``F_p(x_i)/k_i`` and ``-F_n(x_i)/k_i`` depend on where the tip
is. Between events the rate problem is the paper's, solved by the same kernel; the events
are a spring reaching yield, a sliding tip reaching a cell edge where its law changes, and
a snap: a tip entering a cell whose resistance is below its spring's force slides on at
frozen body shape (the other tips sticking or yielding as their laws allow) until its force
drops to the new resistance or it reaches the next edge (Prandtl-Tomlinson's jump). A
snap's loss is the elastic energy it releases, so ``W = E_el + D`` stays exact.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from bristlecrawler.errors import InputError, SolverError
from bristlecrawler.reduced.crawler import PAPER_LENGTH, ReducedCrawler
from bristlecrawler.reduced.model import ReducedModel
from bristlecrawler.reduced.solver import Event, ReducedResult, Stepper, checked_samples
from bristlecrawler.results.drag import summary_of
from bristlecrawler.results.texture import TextureLaw


@dataclass(frozen=True)
class TexturedCrawler(ReducedModel):
    """N bristles on a texture: each bristle's resistance a :class:`TextureLaw` over its
    tip's position.

    Attributes:
        laws: one :class:`TextureLaw` per bristle (its k, resistance over position and
            tip offset).
        segment_lengths: rest lengths of the N-1 body segments, mm.
        start_mm: substrate position of the first bristle's attachment at t = 0, mm (the
            tips start at attachment + tip offset).
    """

    name: ClassVar[str] = "texture"

    laws: tuple[TextureLaw, ...]
    segment_lengths: np.ndarray
    start_mm: float = 0.0

    def __post_init__(self) -> None:
        laws = tuple(self.laws)
        if not laws or not all(isinstance(law, TextureLaw) for law in laws):
            raise InputError("a textured crawler needs one TextureLaw per bristle")
        seg = np.atleast_1d(np.asarray(self.segment_lengths, dtype=float))
        if seg.size + 1 != len(laws):
            raise InputError(f"{len(laws)} bristles need {len(laws) - 1} segment lengths")
        if not (np.all(np.isfinite(seg)) and np.all(seg > 0)):
            raise InputError(f"segment lengths must be positive (mm), got {seg.tolist()}")
        seg.setflags(write=False)
        object.__setattr__(self, "laws", laws)
        object.__setattr__(self, "segment_lengths", seg)
        object.__setattr__(self, "start_mm", float(self.start_mm))

    @classmethod
    def uniform(cls, law: TextureLaw, n_bristles: int = 2, length: float = 100.0, start=0.0):
        """N bristles with the same law evenly over ``length`` mm."""
        if int(n_bristles) != n_bristles or n_bristles < 2:
            raise InputError(f"a crawler needs at least 2 bristles, got {n_bristles}")
        n = int(n_bristles)
        return cls((law,) * n, np.full(n - 1, float(length) / (n - 1)), start)

    @classmethod
    def from_drag(
        cls,
        drag,
        n_bristles: int = 2,
        length: float = PAPER_LENGTH,
        *,
        segment_lengths=None,
        start_mm: float = 0.0,
    ) -> TexturedCrawler:
        """The crawler whose bristles all have a drag test's texture law, its first bristle
        at substrate position ``start_mm`` (mm).

        Args:
            drag: a drag test's :class:`~bristlecrawler.results.drag.DragSummary`,
                its result (anything with ``summarize()`` or ``summary()``, such as
                ``bristlecrawler.crawler.drag.DragResult``) or its summary mapping: reads
                the texture law (a drag test with direction cycle); a sequence of them
                gives each bristle its own.
            n_bristles: number of bristles, spread evenly over ``length`` (mm), unless
                ``segment_lengths`` (mm, N-1 values) places them.
        """
        drags = list(drag) if isinstance(drag, list | tuple) else None
        laws = []
        for d in drags or [drag]:
            law = summary_of(d).texture
            if law is None:
                raise InputError("the drag test gives no texture law (run direction cycle)")
            laws.append(law)
        n = len(laws) if drags else int(n_bristles)
        if segment_lengths is None:
            if n < 2:
                raise InputError(f"a crawler needs at least 2 bristles, got {n_bristles}")
            segment_lengths = np.full(n - 1, float(length) / (n - 1))
        return cls(tuple(laws) if drags else (laws[0],) * n, segment_lengths, start_mm)

    @property
    def n_bristles(self) -> int:
        return len(self.laws)

    @property
    def k(self) -> np.ndarray:
        return np.array([law.k_N_per_mm for law in self.laws])

    @property
    def length(self) -> float:
        return float(self.segment_lengths.sum())

    def paper_crawler(self) -> ReducedCrawler:
        """The paper's crawler with each law's mean F_p and mean finite F_n (at least F_p):
        what one F_p and one F_n per bristle make of this texture."""
        fp = np.array([law.mean_fp_N for law in self.laws])
        fn = [law.fn_N[np.isfinite(law.fn_N)] for law in self.laws]
        fn = np.array([f.mean() if f.size else np.inf for f in fn])
        fn = np.where(np.isfinite(fn), np.maximum(fn, fp), 10.0 * fp)
        return ReducedCrawler(k=self.k, fp=fp, fn=fn, segment_lengths=self.segment_lengths)

    def check_stroke(self, max_shortening) -> None:
        self.paper_crawler().check_stroke(max_shortening)

    def solve(self, t, shortening, cycle_bounds=None) -> ReducedResult:
        """See :meth:`ReducedModel.solve` (:func:`solve_textured`)."""
        return solve_textured(self, t, shortening, cycle_bounds)

    def texture_laws(self) -> tuple[TextureLaw, ...]:
        """Each bristle's law."""
        return self.laws


class _TextureStepper(Stepper):
    """The paper's rate kernel with yield bounds set from the tips' positions."""

    def __init__(self, crawler: TexturedCrawler, scale: float):
        self.laws = crawler.laws
        self.k = crawler.k
        self.tol = 1e-12 * scale
        self.constant = all(law.is_constant for law in self.laws)
        self.shared = all(law is self.laws[0] for law in self.laws)

    def set_bounds(self, x: np.ndarray) -> None:
        if self.shared:
            self.fp = self.laws[0].forward_resistance(x)
            self.fn = self.laws[0].backward_resistance(x)
        else:
            pairs = zip(self.laws, x, strict=True)
            self.fp, self.fn = np.array(
                [(law.forward_resistance(xi), law.backward_resistance(xi)) for law, xi in pairs]
            ).T
        self.upper = self.fp / self.k
        self.lower = -self.fn / self.k

    def edges(self, x: np.ndarray, xdot: np.ndarray) -> np.ndarray:
        """Parameter increments until each sliding tip reaches its next cell edge."""
        if self.constant:
            return np.full(x.size, np.inf)
        d = np.sign(xdot)
        out = np.full(x.size, np.inf)
        for i in np.flatnonzero(np.abs(xdot) > self.tol):
            edge = float(self.laws[i].next_edge(x[i], d[i]))
            out[i] = max((edge - x[i]) / xdot[i], 0.0)
        return out

    def edge_of(self, i: int, x: float, direction: float) -> float:
        """The edge tip ``i`` at ``x`` reaches next moving in ``direction``, mm."""
        return float(self.laws[i].next_edge(x, direction))

    def slide_loss(self, xdot: np.ndarray) -> float:
        """Friction power of the sliding tips at their cells' resistances, mJ per unit."""
        fwd = np.where(xdot > 0, self.fp * xdot, 0.0)
        fn = np.where(np.isfinite(self.fn), self.fn, 0.0)  # no tip slides into a wall
        bwd = np.where(xdot < 0, -fn * xdot, 0.0)
        return float(np.sum(fwd) + np.sum(bwd))

    def violator(self, e: np.ndarray) -> int | None:
        over = np.maximum(e - self.upper, self.lower - e)
        i = int(np.argmax(over))
        return i if over[i] > self.tol else None

    def snap(self, e, x, X0, t, events):
        """Relax every spring beyond its tip's bounds at frozen body shape; returns
        e, x, X0 and the energy the snaps release (mJ)."""
        k = self.k
        e0 = 0.5 * float(k @ e**2)
        for _ in range(64 * k.size + 64):
            self.set_bounds(x)
            i = self.violator(e)
            if i is None:
                return e, x, X0, e0 - 0.5 * float(k @ e**2)
            sign = 1.0 if e[i] > self.upper[i] else -1.0
            target = self.upper[i] if sign > 0 else self.lower[i]
            self.upper[i], self.lower[i] = np.inf, -np.inf
            da = np.zeros_like(e)
            da[i] = -sign
            v, edot, xdot = self.rate(e, da)
            xdot[i] = sign
            up, lo = self.time_to_yield(e, edot)
            up[i] = lo[i] = np.inf
            to_target = (target - e[i]) / edot[i] if sign * edot[i] < 0 else np.inf
            to_edge = self.edges(x, xdot)
            hits = np.array([up.min(), lo.min(), to_edge.min(), to_target])
            which = int(np.argmin(hits))
            step = float(hits[which])
            if not np.isfinite(step):
                raise SolverError(f"tip {i} snaps without end: no position holds it")
            x_old = x
            e = e + edot * step
            x = x + xdot * step
            X0 = X0 + v * step
            if which == 2:
                j = int(np.argmin(to_edge))
                x[j] = self.edge_of(j, x_old[j], np.sign(xdot[j]))
            elif which == 3:
                e[i] = target
            else:
                j = int(np.argmin(np.minimum(up, lo)))
                e[j] = self.upper[j] if up[j] <= lo[j] else self.lower[j]
        raise SolverError(f"snaps did not settle at t={t:g} s")

    def interval(self, e, x, X0, da, t0, t1, prev_mode, events):
        """Integrate one interval event by event. Returns e, x, X0, mode, dW, dD."""
        remaining, dW, dD, tau0 = 1.0, 0.0, 0.0, 0.0
        k = self.k
        mode = prev_mode
        for _ in range(64 * k.size + 256):
            e, x, X0, lost = self.snap(e, x, X0, t0 + tau0 * (t1 - t0), events)
            dD += lost
            v, edot, xdot = self.rate(e, da)
            new_mode = self.mode(xdot)
            for i in np.flatnonzero(new_mode != mode):
                tt = float(t0 + tau0 * (t1 - t0))
                events.append(Event(tt, int(i), int(mode[i]), int(new_mode[i])))
            mode = new_mode
            up, lo = self.time_to_yield(e, edot)
            to_edge = self.edges(x, xdot)
            hit = np.minimum(np.minimum(up, lo), to_edge)
            i_hit = int(np.argmin(hit))
            step = min(float(hit[i_hit]), remaining)
            e_new = e + edot * step
            dW += float(k @ (0.5 * (e + e_new) * da)) * step
            dD += self.slide_loss(xdot) * step
            x_old = x
            x = x + xdot * step
            X0 = X0 + v * step
            e = e_new
            remaining -= step
            tau0 += step
            if float(hit[i_hit]) <= step:
                if to_edge[i_hit] <= min(up[i_hit], lo[i_hit]):
                    x[i_hit] = self.edge_of(i_hit, x_old[i_hit], np.sign(xdot[i_hit]))
                else:
                    e[i_hit] = self.upper[i_hit] if up[i_hit] <= lo[i_hit] else self.lower[i_hit]
                self.set_bounds(x)
            if remaining <= 1e-15:
                e, x, X0, lost = self.snap(e, x, X0, t1, events)
                return e, x, X0, mode, dW, dD + lost
        raise SolverError(
            f"stick/slip events did not settle within the interval t=[{t0:g}, {t1:g}] s"
        )


def solve_textured(crawler: TexturedCrawler, t, shortening, cycle_bounds=None) -> ReducedResult:
    """The textured crawler's quasi-static evolution for sampled segment shortenings
    (see :func:`bristlecrawler.reduced.solve`; tips start at their attachments plus the
    laws' tip offsets, springs unloaded)."""
    t, s = checked_samples(crawler, t, shortening)
    n = crawler.n_bristles
    a = np.zeros((t.size, n))
    a[:, 1:] = np.cumsum(crawler.segment_lengths - s, axis=1)
    M = t.size
    st = _TextureStepper(crawler, crawler.length + 1.0)
    k = st.k
    offset = np.array([law.tip_offset_mm for law in crawler.laws])
    X0 = np.full(M, crawler.start_mm)
    e = np.zeros((M, n))
    x = np.zeros((M, n))
    x[0] = crawler.start_mm + a[0] + offset
    mode_out = np.zeros((M, n), dtype=np.int8)
    W, D = np.zeros(M), np.zeros(M)
    events: list[Event] = []
    mode = np.zeros(n, dtype=np.int8)
    st.set_bounds(x[0])
    for m in range(M - 1):
        em, xm, X0m, mode, dW, dD = st.interval(
            e[m].copy(), x[m].copy(), X0[m], a[m + 1] - a[m], t[m], t[m + 1], mode, events
        )
        e[m + 1], x[m + 1], X0[m + 1] = em, xm, X0m
        W[m + 1], D[m + 1] = W[m] + dW, D[m] + dD
        mode_out[m + 1] = mode
    bounds = np.asarray(cycle_bounds if cycle_bounds is not None else [0, M - 1], dtype=int)
    return ReducedResult(
        crawler=crawler,
        t=t,
        shortening=s,
        X=X0[:, None] + a - crawler.start_mm,
        x=x,
        force=-k * e,
        state=mode_out,
        elastic_energy=0.5 * (e**2) @ k,
        dissipation=D,
        work=W,
        events=tuple(events),
        cycle_bounds=bounds,
    )
