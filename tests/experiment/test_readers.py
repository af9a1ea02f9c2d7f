"""Reading and writing transducer recordings (CSV, NI TDMS)."""

import numpy as np
import pytest

from bristlecrawler.errors import InputError
from bristlecrawler.experiment import (
    ChannelMap,
    Recording,
    read_recording,
    write_csv,
    write_tdms,
)


@pytest.fixture
def rec():
    t = np.arange(200) / 100.0
    left = np.sin(t)
    left[50:53] = np.nan
    return Recording(t=t, left=left, right=0.5 * np.cos(t), current=np.ones_like(t), source="x")


@pytest.mark.parametrize("ext", [".csv", ".tdms"])
def test_round_trip(rec, tmp_path, ext):
    path = tmp_path / f"r{ext}"
    (write_csv if ext == ".csv" else write_tdms)(rec, path)
    back = read_recording(path)
    np.testing.assert_allclose(back.t, rec.t, atol=1e-9)
    np.testing.assert_allclose(back.left, rec.left, atol=1e-5, equal_nan=True)
    np.testing.assert_allclose(back.right, rec.right, atol=1e-5)
    assert np.isnan(back.left[51]) and back.current is not None


def test_custom_names_signs_and_rate(tmp_path):
    path = tmp_path / "lab.csv"
    path.write_text(
        "# exported by LabVIEW\nRear,Front\n"
        + "".join(f"{-i * 0.1},{i * 0.2}\n" for i in range(20))
    )
    cmap = ChannelMap(time=None, left="Rear", right="Front", left_sign=-1.0, rate_hz=50.0)
    rec = read_recording(path, cmap)
    assert rec.rate_hz == pytest.approx(50.0)
    assert rec.left[5] == pytest.approx(0.5) and rec.right[5] == pytest.approx(1.0)


@pytest.mark.parametrize(
    ("content", "word"),
    [
        ("time_s,left_mm\n" + "0,1\n" * 12, "right-end channel"),
        ("1,2,3\n4,5,6\n", "header"),
        ("time_s,left_mm,right_mm\n0,1\n", "cells"),
        ("time_s,left_mm,right_mm\n" + "".join(f"{i % 5},1,1\n" for i in range(12)), "increasing"),
        ("time_s,left_mm,right_mm\n0,1,1\n", "only"),
    ],
)
def test_unusable_csv_files(tmp_path, content, word):
    path = tmp_path / "bad.csv"
    path.write_text(content)
    with pytest.raises(InputError, match=word):
        read_recording(path)


def test_unusable_files(tmp_path):
    with pytest.raises(InputError, match="not found"):
        read_recording(tmp_path / "none.csv")
    bogus = tmp_path / "x.tdms"
    bogus.write_bytes(b"this is not TDMS at all" * 10)
    with pytest.raises(InputError, match="TDMS"):
        read_recording(bogus)
    with pytest.raises(InputError, match="format"):
        read_recording(tmp_path / "x.xlsx")
