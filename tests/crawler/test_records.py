"""The records of a run (:class:`crawler.record.Records`): rows appended one at a time and
blocks of rows from a driver read back as one stacked column, in order."""

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from bristlecrawler.crawler.record import Records


def row(i):
    return {"t": np.float64(i), "x": np.full((3, 2), float(i))}


def block(start, n, padding):
    """``n`` rows from ``start`` then ``padding`` rows of garbage (a driver's buffer)."""
    t = np.concatenate([np.arange(start, start + n, dtype=float), np.full(padding, -1.0)])
    return {"t": t, "x": t[:, None, None] * np.ones((1, 3, 2))}


@given(st.lists(st.tuples(st.booleans(), st.integers(0, 5), st.integers(0, 3)), max_size=8))
def test_rows_and_blocks_read_back_in_order(parts):
    rec, expected = Records(), []
    for single, n, padding in parts:
        start = len(expected)
        if single:
            rec.append(row(start))
            expected.append(start)
        else:
            rec.extend(block(start, n, padding), n)
            expected.extend(range(start, start + n))
    assert len(rec) == len(expected)
    assert bool(rec) == bool(expected)
    if expected:
        np.testing.assert_array_equal(rec.column("t"), expected)
        assert rec.column("x").shape == (len(expected), 3, 2)
        np.testing.assert_array_equal(rec.column("x")[:, 0, 0], expected)
        assert float(rec.last()["t"]) == expected[-1]


def test_cleared_records_are_empty():
    rec = Records()
    rec.extend(block(0, 4, 2), 4)
    rec.clear()
    assert len(rec) == 0 and not rec
    with pytest.raises(IndexError):
        rec.column("t")
    with pytest.raises(IndexError):
        rec.last()
