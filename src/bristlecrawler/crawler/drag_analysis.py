"""A drag test's record and the reduced-model parameters read from it.

* k: the travel the carriage needs to build the sliding force, as the reduced model's
  spring does: the secant from the force at the start of the first leg until 90 % of
  the way to the leg's sliding force F_p (or F_n); after each reversal the same from the
  force at the turn to the new direction's sliding force (unloading). And the tangent of
  the first loading while the tip sticks (the small-load stiffness beam theory gives).
* F_p, F_n: the mean horizontal force while sliding along and against the grain, as the
  work over whole pitches divided by their length (so the snaps over the grooves count
  with their weight), with the pitch-to-pitch scatter and the peaks.
* the dissipated work per mm of drag (friction and damping).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from bristlecrawler.crawler.record import energy_series
from bristlecrawler.results import keys
from bristlecrawler.results.drag import DragSummary, Sliding
from bristlecrawler.results.variables import Variable, variables_markdown
from bristlecrawler.states import ContactState


@dataclass(frozen=True)
class DragResult:
    """Time series of a drag test (index m) and what they give.

    Attributes:
        t: s from the start of the drag. x: carriage displacement, mm. lift: carriage
            vertical displacement, mm. force_x: horizontal force the carriage applies, N
            (+x): what its clamp transmits into the bristle. contact: force of the
            substrate on the bristle (x, y), N, (M, 2).
        tip: tip position, mm, (M, 2). tip_state: :class:`ContactState` of the tip.
        energies: series in mJ (elastic, kinetic, potential, friction, damping, external).
        pitch: groove pitch, mm. load: vertical load on the bristle, N. mu: friction
        coefficient. legs: (start, end) sample indices of each leg, with its direction
        (+1 along, -1 against). stats: counters of the solve.
    """

    t: np.ndarray
    x: np.ndarray
    lift: np.ndarray
    force_x: np.ndarray
    contact: np.ndarray
    tip: np.ndarray
    tip_state: np.ndarray
    energies: dict
    pitch: float
    load: float
    mu: float
    legs: tuple[tuple[int, int, int], ...]
    frame_nodes: np.ndarray = field(repr=False, default=None)
    stats: dict = field(default_factory=dict)

    # -- the reduced model's parameters ----------------------------------------------------
    def first_slip(self, leg: int) -> int | None:
        """Index of the first sample of leg ``leg`` at which the tip slips."""
        a, b, _ = self.legs[leg]
        a += leg > 0  # a leg's first sample is the last of the one before
        slips = np.flatnonzero(self.tip_state[a : b + 1] == ContactState.SLIP)
        return None if slips.size == 0 else a + int(slips[0])

    def stick_slope(self, leg: int = 0) -> float:
        """dF/dx (N/mm) over the leg's stick phase (from a tenth of the way to the first
        slip up to it; least squares), or NaN when the tip never sticks there: the
        tangent stiffness at the start of the loading."""
        a, _, _ = self.legs[leg]
        k = self.first_slip(leg)
        if k is None or k - a < 4:
            return math.nan
        x, f = self.x[a:k], self.force_x[a:k]
        keep = np.abs(x - x[0]) >= 0.1 * abs(x[-1] - x[0])
        if keep.sum() < 3:
            return math.nan
        return float(np.polyfit(x[keep], f[keep], 1)[0])

    def secant_stiffness(self, leg: int = 0, share: float = 0.9) -> float:
        """Force change over carriage travel (N/mm) from the leg's start until the force
        has covered ``share`` of the way to the sliding force of its direction (+F_p
        along, -F_n against); NaN when it never gets there. It is the reduced model's k:
        its spring takes (F_slide - F_start) / k of travel to slide. Short of the whole
        way, so that the ripple of the sliding force does not move the end point."""
        a, b, d = self.legs[leg]
        slide = self.sliding(d)
        if slide is None:
            return math.nan
        f0 = self.force_x[a]
        target = f0 + share * (d * slide.mean - f0)
        reached = np.flatnonzero(d * (self.force_x[a : b + 1] - target) >= 0.0)
        if reached.size == 0 or reached[0] == 0:
            return math.nan
        i = a + int(reached[0])
        f1, f2 = self.force_x[i - 1], self.force_x[i]
        # The crossing between the two samples (at the second where the force is flat).
        w = (target - f1) / (f2 - f1) if f2 != f1 else 1.0
        x_at = self.x[i - 1] + w * (self.x[i] - self.x[i - 1])
        travel = abs(x_at - self.x[a])
        return float(abs(target - f0) / travel) if travel > 0 else math.nan

    def sliding(self, direction: int) -> Sliding | None:
        """The sliding force of the legs in ``direction`` (+1 along, -1 against), over the
        whole pitches after each leg's first slip; None without a whole pitch."""
        means, peaks = [], []
        for leg, (_, b, d) in enumerate(self.legs):
            k = self.first_slip(leg)
            if d != direction or k is None:
                continue
            x, f = self.x[k : b + 1], self.force_x[k : b + 1]
            n = int(abs(x[-1] - x[0]) // self.pitch)
            for j in range(n):
                lo = x[0] + d * j * self.pitch
                means.append(_mean_over(x, f, lo, lo + d * self.pitch))
            if n:
                peaks.append(float(np.max(np.abs(f))))
        if not means:
            return None
        m = np.abs(np.asarray(means))
        return Sliding(
            float(m.mean()),
            float(m.std()),
            float(m.min()),
            float(m.max()),
            float(max(peaks)),
            len(m),
        )

    def dissipation_per_mm(self) -> float:
        """Friction and damping dissipation over the carriage's whole travel, mJ/mm."""
        travel = float(np.sum(np.abs(np.diff(self.x))))
        lost = self.energies["friction"][-1] + self.energies["damping"][-1]
        return float(lost / max(travel, 1e-300))

    def summarize(self) -> DragSummary:
        """The parameters as a typed result (NaN where the test does not give one)."""
        along, against = self.sliding(+1), self.sliding(-1)
        unload = [self.secant_stiffness(i) for i in range(1, len(self.legs))]
        unload = [v for v in unload if math.isfinite(v)]
        return DragSummary(
            k=self.secant_stiffness(0),
            k_unload=float(np.mean(unload)) if unload else math.nan,
            k_initial=self.stick_slope(0),
            along=along,
            against=against,
            mu_load=self.mu * self.load,
            load=self.load,
            dissipation_per_mm=self.dissipation_per_mm(),
            energy_balance_rel_error=self.energy_balance_rel_error(),
            steps=int(self.stats.get("steps", self.t.size - 1)),
            newton_iterations=int(self.stats.get("newton_iterations", 0)),
            wall_time=float(self.stats.get("wall_time_s", math.nan)),
            texture=self.texture(),
            settle_speed=float(self.stats.get("settle_speed_mm_s", math.nan)),
            settle_creep=float(self.stats.get("settle_creep_mm", math.nan)),
        )

    def summary(self) -> dict:
        """The parameters (units in the keys; NaN where the test does not give one):
        :meth:`summarize` as a JSON-ready mapping, with the run's ``warnings``."""
        summary = self.summarize()
        warning = self._unsettled(summary.fp_over_k)
        return summary.to_dict() | {"warnings": [warning] if warning else []}

    def unsettled(self) -> str | None:
        """A warning when the carriage still moved at the end of the gravity step by
        enough to matter: the distance it would still creep there (``settle_creep_mm``)
        above :data:`~bristlecrawler.crawler.history.SETTLE_CREEP_LIMIT` times the first
        loading's travel to sliding, F_p / k (None: settled, or not recorded). The first
        loading's slope depends on how a rig that still rings was stepped
        (docs/findings.md)."""
        return self._unsettled(self.summarize().fp_over_k)

    def _unsettled(self, scale: float) -> str | None:
        from bristlecrawler.crawler.history import settle_warning

        return settle_warning(
            self.stats,
            scale,
            "carriage",
            f"F_p / k = {scale:.3g} mm of travel to sliding",
            "k depends on the gravity step's time steps",
        )

    def texture(self, cells: int | None = None):
        """The bristle's :class:`~bristlecrawler.results.texture.TextureLaw` (resistance
        over the tip's position within a pitch, both ways), or None when the test did not
        slide both ways (see :mod:`.drag_texture`)."""
        from bristlecrawler.crawler.drag_texture import DEFAULT_CELLS, texture_law
        from bristlecrawler.errors import InputError

        try:
            return texture_law(self, cells or DEFAULT_CELLS)
        except InputError:
            return None

    def energy_balance_rel_error(self) -> float:
        e = self.energies
        r = e["external"] - sum(e[k] for k in ("elastic", "kinetic", "potential"))
        r = r - e["friction"] - e["damping"]
        return float(np.max(np.abs(r)) / max(float(np.max(np.abs(e["external"]))), 1e-300))

    def to_dataset(self, attrs: dict | None = None):
        """The series as an xarray Dataset (dims time, xy; cell for the texture law): the
        variables of :data:`DRAG_VARIABLES`, units and meaning in each one's attrs."""
        import xarray as xr

        summary = self.summary()
        src = _DragSource(self, summary["texture"])
        ds = xr.Dataset(
            {v.name: v.variable(src) for v in DRAG_VARIABLES if v.when is None or v.when(src)},
            coords={"time": ("time", self.t, {"units": "s"}), "xy": ["x", "y"]},
            attrs={
                "model": "bristlecrawler drag test",
                "pitch_mm": self.pitch,
                "load_N": self.load,
                "mu": self.mu,
            },
        )
        clean = {k: v for k, v in summary.items() if isinstance(v, int | float)}
        ds.attrs.update(clean | (attrs or {}))
        ds.attrs["legs"] = np.asarray(self.legs, dtype=np.int64).ravel()
        return ds

    @classmethod
    def from_dataset(cls, ds, legs=None) -> DragResult:
        """The result back from :meth:`to_dataset`'s Dataset (``legs``: (start, end,
        direction) per leg, for a file written without them)."""
        legs = legs if legs is not None else np.asarray(ds.attrs["legs"]).reshape(-1, 3)
        energies = {
            name[len("energy_") :]: ds[name].values
            for name in ds.data_vars
            if name.startswith("energy_")
        }
        return cls(
            t=ds["time"].values,
            x=ds["carriage_x"].values,
            lift=ds["carriage_lift"].values,
            force_x=ds["force_x"].values,
            contact=ds["contact_force"].values,
            tip=ds["tip_position"].values,
            tip_state=ds["tip_state"].values.astype(int),
            energies=energies,
            pitch=float(ds.attrs["pitch_mm"]),
            load=float(ds.attrs["load_N"]),
            mu=float(ds.attrs["mu"]),
            legs=tuple(tuple(int(v) for v in leg) for leg in legs),
            stats={
                k: ds.attrs[k]
                for k in ("steps", "newton_iterations", "settle_speed_mm_s", "settle_creep_mm")
                if k in ds.attrs
            },
        )


@dataclass(frozen=True)
class _DragSource:
    """What ``drag.nc`` is made of: the result and its texture law (a dict, or None)."""

    r: DragResult
    law: dict | None


def _on_texture(src: _DragSource) -> bool:
    return src.law is not None


def _cell_centres(law: dict) -> np.ndarray:
    n = len(law[keys.FP_N])
    return (np.arange(n) + 0.5) * law["cell_mm"] + law["origin_mm"]


def _energy(key: str, description: str) -> Variable:
    return Variable(f"energy_{key}", ("time",), "mJ", description, lambda s: s.r.energies[key])


#: The variables of ``drag.nc``, each declared once: the dataset
#: (:meth:`DragResult.to_dataset`) and the output reference's table are made from these.
DRAG_VARIABLES: tuple[Variable, ...] = (
    Variable("carriage_x", ("time",), "mm", "carriage travel", lambda s: s.r.x),
    Variable("carriage_lift", ("time",), "mm", "carriage rise", lambda s: s.r.lift),
    Variable(
        "force_x",
        ("time",),
        "N",
        "horizontal force of the carriage (+x): what its clamp transmits into the bristle",
        lambda s: s.r.force_x,
    ),
    Variable(
        "contact_force",
        ("time", "xy"),
        "N",
        "substrate force on the bristle",
        lambda s: s.r.contact,
    ),
    Variable("tip_position", ("time", "xy"), "mm", "the bristle's tip", lambda s: s.r.tip),
    Variable(
        "tip_state",
        ("time",),
        "",
        "contact state of the tip",
        lambda s: s.r.tip_state.astype(np.int8),
        flags=tuple((int(c), c.name.lower()) for c in ContactState),
    ),
    _energy(
        "elastic", "elastic energy of the bristle and contact penalties, from the first record"
    ),
    _energy("kinetic", "kinetic energy, from the first record"),
    _energy("potential", "gravitational potential energy, from the first record"),
    _energy("friction", "energy dissipated by friction"),
    _energy("damping", "energy dissipated by Rayleigh damping"),
    _energy("external", "work of the carriage"),
    Variable(
        "texture_position",
        ("cell",),
        "mm",
        "texture law: centre of each cell of the pitch",
        lambda s: _cell_centres(s.law),
        when=_on_texture,
    ),
    Variable(
        "texture_fp",
        ("cell",),
        "N",
        "texture law: resistance along the grain in each cell (F_p(x)); attributes "
        "pitch_mm, origin_mm",
        lambda s: np.asarray(s.law[keys.FP_N], dtype=float),
        when=_on_texture,
        more=lambda s: {"pitch_mm": s.law["pitch_mm"], "origin_mm": s.law["origin_mm"]},
    ),
    Variable(
        "texture_fn",
        ("cell",),
        "N",
        "texture law: resistance against the grain in each cell (F_n(x), inf at a wall); "
        "attributes k_N_per_mm, tip_offset_mm",
        lambda s: np.array([np.inf if v == "inf" else v for v in s.law[keys.FN_N]], float),
        when=_on_texture,
        more=lambda s: {
            keys.K_N_PER_MM: s.law[keys.K_N_PER_MM],
            "tip_offset_mm": s.law["tip_offset_mm"],
        },
    ),
)


def drag_variables_markdown() -> str:
    """The reference table of ``drag.nc``'s variables."""
    return variables_markdown(DRAG_VARIABLES)


def _mean_over(x, f, lo, hi) -> float:
    """Mean of f over x in [lo, hi] (either order), weighted by x (the work over the
    interval divided by its length), with the end values interpolated."""
    a, b = min(lo, hi), max(lo, hi)
    order = np.argsort(x)
    xs, fs = x[order], f[order]
    inner = (xs > a) & (xs < b)
    xx = np.concatenate([[a], xs[inner], [b]])
    ff = np.concatenate([[np.interp(a, xs, fs)], fs[inner], [np.interp(b, xs, fs)]])
    return float(np.trapezoid(ff, xx) / (b - a))


def result_of(ctx) -> DragResult:
    """The :class:`DragResult` of a drag ctx's records."""
    dm, records = ctx.crawler, ctx.records
    settle = dm.spec.actuation.settle_time
    t = records.column("t").astype(float) - settle
    x = records.column("stretch")[:, 0].astype(float)
    drive = records.column("fc")[:, 0].astype(float)
    fx = records.column("push")[:, 0].astype(float)
    en, nodes = records.column("energies"), records.column("x")
    knots_t = dm.test.leg_times()
    edges = np.searchsorted(t, knots_t - 1e-9)
    edges[-1] = t.size - 1
    first = -1 if dm.test.direction == "against" else 1
    legs = tuple(
        (int(edges[i]), int(edges[i + 1]), first * (1 if i % 2 == 0 else -1))
        for i in range(len(knots_t) - 1)
    )
    stats = {
        "steps": len(records) - 1,
        "newton_iterations": ctx.iterations,
        "rejected_steps": ctx.rejected,
        "first_frequency_hz": ctx.omega1 / (2 * math.pi),
        **ctx.stats,
    }
    return DragResult(
        t=t,
        x=x,
        lift=records.column("lift").astype(float),
        force_x=fx,
        contact=records.column("contact"),
        tip=nodes[:, dm.chain[-1]],
        tip_state=records.column("tip_state")[:, 0].astype(int),
        energies=energy_series(t, drive, x, en),
        pitch=dm.spec.substrate.period,
        load=dm.load,
        mu=dm.spec.contact.mu,
        legs=legs,
        frame_nodes=nodes,
        stats=stats,
    )
