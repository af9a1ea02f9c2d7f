"""crawler.nc holds the declared quantities (crawler/quantities.py) with their units,
dims and descriptions, and nothing else; the output reference is made from them. (A run
of the FE crawler writes every one of them: tests/crawler/test_fe_crawler_short.py.)"""

import dataclasses

import numpy as np
import pytest

from bristlecrawler.crawler import quantities as quant
from bristlecrawler.crawler.quantities import MARKER, QUANTITIES, Quantity, quantities_markdown

from .kinematic import kinematic_history

DECLARED = {q.name: q for q in QUANTITIES}


def _check_declared(ds):
    """Every variable of ``ds`` is declared, with the declaration's dims and attributes."""
    assert set(ds.variables) <= set(DECLARED), set(ds.variables) - set(DECLARED)
    for name in ds.variables:
        q = DECLARED[name]
        v = ds[name]
        assert v.dims == q.dims, name
        assert (name in ds.coords) is q.coordinate, name
        assert v.attrs.get("units", "") == q.unit, name
        if not q.coordinate:
            assert v.attrs["long_name"] == q.description, name
        if q.flags:
            assert v.attrs["flag_meanings"].split() == list(q.flags), name
            assert set(np.unique(v.values)) <= set(range(len(q.flags))), name


def test_names_are_unique_and_every_quantity_has_a_unit_or_codes():
    assert len(DECLARED) == len(QUANTITIES)
    for q in QUANTITIES:
        assert q.description and q.dims, q.name
        # A quantity without a unit is a code, an index or the xy labels.
        assert q.unit or q.flags or q.dtype or q.name == "xy", q.name


def test_a_kinematic_history_writes_what_it_has():
    """The stand-in has three of the energies and no per-segment series: those are left
    out, the rest written as declared."""
    h = kinematic_history(cycles=1, samples=20)
    ds = h.to_dataset()
    _check_declared(ds)
    absent = {"segment_shortening", "segment_force", "energy_kinetic", "energy_potential"}
    absent |= {"energy_damping"}
    assert set(ds.variables) == set(DECLARED) - absent


def test_an_undeclared_series_cannot_appear():
    h = kinematic_history(cycles=1, samples=20)
    odd = dataclasses.replace(
        h,
        energies=h.energies | {"magnetic": h.energies["elastic"]},
        quantities={"tip_temperature": np.zeros_like(h.t)},
    )
    with pytest.warns(UserWarning, match="energies.magnetic, tip_temperature"):
        ds = odd.to_dataset()
    assert "energy_magnetic" not in ds and "tip_temperature" not in ds
    assert set(ds.variables) == set(h.to_dataset().variables)


def test_a_new_quantity_is_one_declaration(monkeypatch):
    """A declaration whose name is not a history attribute: the history keeps it in
    ``quantities`` (history_fields), and the dataset writes it with its unit."""
    h = kinematic_history(cycles=1, samples=20)
    extra = Quantity(
        "tip_speed",
        ("time", "bristle"),
        "mm/s",
        "speed of the bristle tip",
        from_records=lambda r: np.gradient(r.tips, r.t, axis=0),
    )
    records = type("Records", (), {"t": h.t, "tips": h.tip_position[..., 0]})()
    attributes = frozenset(f.name for f in dataclasses.fields(h))
    fields = quant.history_fields(records, attributes, [extra])
    assert list(fields) == ["quantities"]
    monkeypatch.setattr(quant, "QUANTITIES", (*QUANTITIES, extra))
    monkeypatch.setattr("bristlecrawler.crawler.dataset.QUANTITIES", quant.QUANTITIES)
    ds = dataclasses.replace(h, **fields).to_dataset()
    assert ds["tip_speed"].attrs == {"units": "mm/s", "long_name": "speed of the bristle tip"}
    assert ds["tip_speed"].dims == ("time", "bristle")
    assert "`tip_speed` | time, bristle | mm/s |" in quantities_markdown(quant.QUANTITIES)


def test_the_output_reference_is_made_from_the_declarations():
    from pathlib import Path

    page = Path(__file__).resolve().parents[2] / "docs" / "reference" / "outputs.md"
    assert MARKER in page.read_text()  # the hook puts quantities_markdown() there
    table = quantities_markdown()
    for q in QUANTITIES:
        assert f"| `{q.name}` | {', '.join(q.dims)} | {q.unit} |" in table, q.name
