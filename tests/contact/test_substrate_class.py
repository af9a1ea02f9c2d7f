"""The substrate class: a substrate's period and its convex corners follow from its
profile, and every shipped kind says so."""

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from bristlecrawler.contact import Flat, Grooves, Polyline, Sawtooth

# Heights of 0 or at least a nanometre: below that the turn of the profile underflows
# (a bump of 1e-311 mm is not geometry).
HEIGHTS = st.one_of(st.just(0.0), st.floats(1e-6, 0.5), st.floats(-0.5, -1e-6))


@given(st.lists(HEIGHTS, min_size=1, max_size=6), st.floats(0.5, 4.0))
def test_a_polylines_corners_are_where_its_boundary_turns_into_the_solid(heights, period):
    """``period`` is the profile's, and ``has_corners`` holds where the profile turns:
    a bump is convex somewhere, a profile that never turns has no corner."""
    xs = np.linspace(0.0, period, len(heights) + 2)
    pts = np.column_stack([xs, [0.0, *heights, 0.0]])
    s = Polyline(points=pts)
    assert s.period == pytest.approx(period)
    assert s.has_corners == any(h != 0.0 for h in heights)


def test_the_shipped_substrates_say_whether_they_have_corners():
    assert not Flat(height=0.3).has_corners and Flat().period == 1.0
    assert Grooves(width=1.0, depth=0.25, pitch=2.0).has_corners
    assert Grooves(width=1.0, depth=0.25, pitch=2.0, fillet_top=0.05).period == 2.0
    assert Sawtooth(pitch=1.5, height=0.2).has_corners
