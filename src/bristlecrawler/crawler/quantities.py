"""Every quantity a finite-element crawler run records, declared once.

A :class:`Quantity` is one variable of ``crawler.nc``: its name, dimensions, unit and
description, and how it is computed, from the observer's records of a run
(:class:`RunRecords`, for :func:`history_fields` and so the :class:`CrawlerHistory`) or
from the other quantities of a history (``delta``, the balance residual). The dataset
(:mod:`.dataset`) writes these and nothing else, and the output reference
(docs/reference/outputs.md) is generated from them (:func:`quantities_markdown`).

Adding a quantity is one declaration in :data:`QUANTITIES`, and a column of the record
(:func:`.record.observer`) where the record does not yet hold what it needs; a history
keeps a quantity without an attribute of its own in ``CrawlerHistory.quantities``.

Sign conventions: x to the right (the direction of motion along the grain), y up; the
shortening is positive when the body is shorter than at rest; a connector force is
positive when it pulls the segment's ends together.
"""

from __future__ import annotations

import dataclasses
import functools
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from bristlecrawler.contact.profile import drawing
from bristlecrawler.states import ContactState

#: Marker of the output reference page that :func:`quantities_markdown` replaces.
MARKER = "<!-- crawler-variables -->"


class RunRecords:
    """What a quantity is computed from: the records of a run's accepted steps
    (:class:`.record.Records`, the observer's columns), the built crawler and its spec.
    The columns and the energy series are computed once, on first use."""

    def __init__(self, records, crawler, spec) -> None:
        self.records, self.crawler, self.spec = records, crawler, spec
        self._columns: dict[str, np.ndarray] = {}

    def column(self, key: str) -> np.ndarray:
        """One entry of every record stacked on a leading axis."""
        if key not in self._columns:
            self._columns[key] = self.records.column(key)
        return self._columns[key]

    @property
    def time(self) -> np.ndarray:
        """Times of the records from the start of the stroke, s."""
        return self.column("t") - self.spec.actuation.settle_time

    @property
    def x(self) -> np.ndarray:
        """Node positions, mm, (M, P, 2)."""
        return self.column("x")

    @functools.cached_property
    def energies(self) -> dict[str, np.ndarray]:
        """The energy series (:func:`.record.energy_series`), mJ."""
        from bristlecrawler.crawler.record import energy_series

        c = self.column
        return energy_series(c("t"), c("fc"), c("stretch"), c("energies"))

    def substrate_drawing(self) -> np.ndarray:
        """The substrate's surface 5 mm either side of every recorded node, mm, (K, 2)."""
        x = self.x[..., 0]
        profile = self.spec.substrate.profile()
        return np.asarray(drawing(profile, x.min() - 5.0, x.max() + 5.0))


@dataclass(frozen=True)
class Quantity:
    """One recorded quantity: a variable of ``crawler.nc``.

    Attributes:
        name: the variable's name.
        dims: its dimensions.
        unit: its ``units`` attribute ("": a code or an index, no unit).
        description: its ``long_name`` attribute (a coordinate's is for the reference
            page only).
        from_records: its value in the history, from a run's :class:`RunRecords`; None
            for a quantity computed from the history (``from_history``).
        from_history: its value in the dataset, from a :class:`CrawlerHistory`; None: the
            history's ``field`` as it is. None from either means the history does not
            have it, and the variable is left out.
        field: where the history keeps it: an attribute (``"s"``) or an entry of a
            mapping attribute (``"energies.elastic"``); default: ``name``. A name that is
            not an attribute of :class:`CrawlerHistory` is kept in its ``quantities``.
        flags: the meanings of the codes 0, 1, ... (``flag_values`` and
            ``flag_meanings``).
        dtype: the stored type (codes and indices are small integers).
        note: more about it for the reference page (Markdown).
        coordinate: a coordinate of the dataset (only its unit is written).
    """

    name: str
    dims: tuple[str, ...]
    unit: str
    description: str
    from_records: Callable[[RunRecords], Any] | None = None
    from_history: Callable[[Any], Any] | None = None
    field: str = ""
    flags: tuple[str, ...] = ()
    dtype: str | None = None
    note: str = ""
    coordinate: bool = False

    @property
    def home(self) -> str:
        """Where the history keeps it (``field``, else ``name``)."""
        return self.field or self.name

    def value(self, h):
        """The dataset's values of this quantity for the history ``h`` (a
        :class:`.history.CrawlerHistory`; None: absent)."""
        if self.from_history is not None:
            v = self.from_history(h)
        else:
            head, _, key = self.home.partition(".")
            if head not in {f.name for f in dataclasses.fields(h)}:
                v = h.quantities.get(self.name)
            else:
                v = getattr(h, head)
                v = v.get(key) if key and v is not None else v
        if v is None or self.dtype is None:
            return v
        return np.asarray(v).astype(self.dtype)

    def attrs(self) -> dict:
        """The variable's attributes: units, the codes' meanings, long_name."""
        out: dict[str, Any] = {"units": self.unit} if self.unit else {}
        if self.flags:
            out["flag_values"] = np.arange(len(self.flags), dtype=np.int8)
            out["flag_meanings"] = " ".join(self.flags)
        if not self.coordinate:
            out["long_name"] = self.description
        return out


def _zero_sign(v):
    # The first record's shortening is -0.0 (a rest length minus itself, negated); the
    # file has 0.0.
    return None if v is None else v + 0.0


def _energy(key: str, description: str) -> Quantity:
    return Quantity(
        f"energy_{key}",
        ("time",),
        "mJ",
        description,
        from_records=lambda r: r.energies[key],
        field=f"energies.{key}",
    )


def _residual(h) -> np.ndarray:
    r = h.energy_balance_residual()
    return r - r[0]


#: The recorded quantities, in the order of the file's variables.
QUANTITIES: tuple[Quantity, ...] = (
    Quantity("time", ("time",), "s", "time of each accepted step from the start of the "
             "stroke (the end of the gravity step, `actuation.settle_time`)",
             from_records=lambda r: r.time, field="t", coordinate=True),
    Quantity("frame_time", ("frame",), "s", "times of the drawn frames",
             from_records=lambda r: r.time, field="frame_t", coordinate=True),
    Quantity("xy", ("xy",), "", "the labels x, y",
             from_history=lambda h: np.array(["x", "y"]), coordinate=True),
    Quantity("s", ("time",), "mm", "shortening s (of the first segment)",
             from_records=lambda r: r.column("stretch")[:, 0],
             from_history=lambda h: _zero_sign(h.s)),
    Quantity("delta", ("time",), "mm", "right-end displacement Delta",
             from_history=lambda h: h.delta),
    Quantity("left", ("time", "xy"), "mm", "left end (first body node)",
             from_records=lambda r: r.x[:, r.crawler.left]),
    Quantity("right", ("time", "xy"), "mm", "right end (last body node)",
             from_records=lambda r: r.x[:, r.crawler.right]),
    Quantity("connector_force", ("time",), "N",
             "connector force F_c of the first segment (pulling)",
             from_records=lambda r: r.column("fc")[:, 0]),
    Quantity("connector_work", ("time",), "mJ",
             "connector work W_c = sum over segments of int F_c ds",
             from_records=lambda r: r.energies["external"]),
    Quantity("tip_position", ("time", "bristle", "xy"), "mm",
             "bristle tip position (bristles from the left)",
             from_records=lambda r: np.stack([r.x[:, t] for t in r.crawler.tips], axis=1)),
    Quantity("tip_state", ("time", "bristle"), "", "contact state of the bristle tip",
             from_records=lambda r: r.column("tip_state"), dtype="int8",
             flags=tuple(s.name.lower() for s in ContactState)),
    Quantity("energy_balance_residual", ("time",), "mJ",
             "energy balance residual: W_c minus stored energies and dissipations",
             from_history=_residual,
             note="the integrator's loss at snaps "
             "([findings](../findings.md#the-energy-balance-residual-is-the-integrators-loss-at-snaps))"),
    Quantity("frame_nodes", ("frame", "node", "xy"), "mm", "node positions of the drawn frames",
             from_records=lambda r: r.x),
    Quantity("lines", ("line", "end"), "", "nodes of the drawing's line cells",
             from_records=lambda r: r.crawler.lines, dtype="int32"),
    Quantity("line_kind", ("line",), "", "kind of line cell",
             from_records=lambda r: r.crawler.line_kind, dtype="int8",
             flags=("body", "link", "bristle")),
    Quantity("substrate_xy", ("substrate_point", "xy"), "mm",
             "substrate surface (drawing, fillets left out)",
             from_records=RunRecords.substrate_drawing),
    Quantity("segment_shortening", ("time", "segment"), "mm", "shortening of each body segment",
             from_records=lambda r: r.column("stretch"),
             from_history=lambda h: _zero_sign(h.segment_shortening)),
    Quantity("segment_force", ("time", "segment"), "N",
             "connector force of each segment's actuator (pulling)",
             from_records=lambda r: r.column("fc")),
    Quantity("node_thickness", ("node",), "mm",
             "bristle section thickness at the node (0 elsewhere)",
             from_records=lambda r: r.crawler.node_thickness()),
    _energy("elastic",
            "elastic energy of the bristles and contact penalties, from the first record"),
    _energy("kinetic", "kinetic energy, from the first record"),
    _energy("potential", "gravitational potential energy, from the first record"),
    _energy("friction", "energy dissipated by friction"),
    _energy("damping", "energy dissipated by Rayleigh damping"),
    _energy("external", "external work (the connector's, W_c)"),
)  # fmt: skip


def history_fields(
    run: RunRecords, attributes: frozenset[str], quantities: Sequence[Quantity] = QUANTITIES
) -> dict:
    """The history's arguments that the quantities computed from records fill: mapping
    entries gathered into their mapping, quantities that are not among the history's
    ``attributes`` (the field names of :class:`.history.CrawlerHistory`, given by the
    caller so that this module needs no history) into ``quantities``."""
    out: dict[str, Any] = {}
    for q in quantities:
        if q.from_records is None:
            continue
        value = q.from_records(run)
        head, _, key = q.home.partition(".")
        if head not in attributes:
            out.setdefault("quantities", {})[q.name] = value
        elif key:
            out.setdefault(head, {})[key] = value
        else:
            out[head] = value
    return out


def quantities_markdown(quantities: Sequence[Quantity] = QUANTITIES) -> str:
    """The table of ``crawler.nc``'s variables for the output reference."""
    rows = ["| variable | dims | unit | meaning |", "|---|---|---|---|"]
    for q in quantities:
        meaning = q.description
        if q.flags:
            meaning += ": " + ", ".join(f"{i} {f}" for i, f in enumerate(q.flags))
        if q.note:
            meaning += f"; {q.note}"
        meaning = meaning.replace("|", "\\|")
        rows.append(f"| `{q.name}` | {', '.join(q.dims)} | {q.unit} | {meaning} |")
    return "\n".join(rows) + "\n"
