"""``drag.nc`` holds exactly the variables :data:`DRAG_VARIABLES` declares, each with its
unit and meaning, and reads back to the same result."""

import dataclasses

import numpy as np
import pytest
import xarray as xr

from bristlecrawler.crawler.drag_analysis import DRAG_VARIABLES, DragResult
from bristlecrawler.io.netcdf import write_netcdf
from structures import spring_drag

ENERGIES = ("elastic", "kinetic", "potential", "friction", "damping", "external")


def _spring_drag():
    """The reduced model's bristle dragged 4 mm along and back (a result that slides
    both ways, so it has a texture law), with noise in the series the analysis does not
    read, so that a mixed-up variable shows."""
    r = spring_drag(n=401, f0=0.0)
    m = r.t.size
    rng = np.random.default_rng(0)
    return dataclasses.replace(
        r,
        lift=rng.normal(size=m),
        contact=rng.normal(size=(m, 2)),
        tip=np.stack([r.x - r.force_x / 0.8, np.zeros(m)], axis=1),
        energies={name: rng.normal(size=m) for name in ENERGIES},
    )


@pytest.mark.parametrize("both_ways", [True, False])
def test_the_file_has_exactly_the_declared_variables_with_their_units(tmp_path, both_ways):
    r = _spring_drag()
    if not both_ways:
        r = dataclasses.replace(r, legs=r.legs[:1])
    write_netcdf(r.to_dataset(), tmp_path / "drag.nc")
    with xr.open_dataset(tmp_path / "drag.nc") as ds:
        ds.load()
    texture = {"texture_position", "texture_fp", "texture_fn"}
    declared = {v.name: v for v in DRAG_VARIABLES}
    expected = set(declared) if both_ways else set(declared) - texture
    assert set(ds.data_vars) == expected
    for name in expected:
        v, attrs = declared[name], ds[name].attrs
        assert attrs["long_name"] == v.description, name
        assert attrs.get("units", "") == v.unit, name
        assert ds[name].dims == v.dims, name
    assert ds["time"].attrs["units"] == "s"
    assert list(ds["tip_state"].attrs["flag_meanings"].split()) == ["open", "stick", "slip"]
    if both_ways:
        assert ds["texture_fp"].attrs["pitch_mm"] == pytest.approx(1.0)
        assert ds["texture_fn"].attrs["k_N_per_mm"] == pytest.approx(0.8, rel=1e-6)


def test_the_file_reads_back_to_the_same_series(tmp_path):
    r = _spring_drag()
    write_netcdf(r.to_dataset(), tmp_path / "drag.nc")
    with xr.open_dataset(tmp_path / "drag.nc") as ds:
        back = DragResult.from_dataset(ds.load())
    for name in ("t", "x", "lift", "force_x", "contact", "tip", "tip_state"):
        np.testing.assert_array_equal(getattr(back, name), getattr(r, name), err_msg=name)
    for name in ENERGIES:
        np.testing.assert_array_equal(back.energies[name], r.energies[name], err_msg=name)
    assert back.legs == r.legs
    assert back.summary()["fp_N"] == r.summary()["fp_N"]
