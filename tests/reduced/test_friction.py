"""The directional friction law, eq. (4.1)."""

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from bristlecrawler.errors import InputError
from bristlecrawler.reduced import DirectionalFriction

forces = st.floats(0.01, 10.0)


@given(fp=forces, ratio=st.floats(1.0, 10.0), v=st.floats(-1e3, 1e3))
def test_force_opposes_sliding_and_dissipation_is_nonnegative(fp, ratio, v):
    law = DirectionalFriction.with_ratio(fp, ratio)
    f = float(law.force(v, stick_force=0.0))
    # The force on the crawler opposes the tip's sliding: its power is never positive.
    assert f * v <= 0.0
    assert law.is_admissible(f)
    # Dissipation of a slip increment equals minus the work of the friction force.
    assert law.dissipation(v) == pytest.approx(-f * v, rel=1e-12, abs=1e-300)


@given(fp=forces, ratio=st.floats(1.0, 10.0), f=st.floats(-20.0, 20.0))
def test_stick_force_projected_on_stick_interval(fp, ratio, f):
    law = DirectionalFriction.with_ratio(fp, ratio)
    lo, hi = law.stick_interval
    assert lo == -fp and hi == pytest.approx(ratio * fp)
    assert float(law.force(0.0, stick_force=f)) == pytest.approx(np.clip(f, lo, hi))


def test_law_is_directional():
    law = DirectionalFriction(0.45, 1.35)
    assert law.force(1.0) == -0.45 and law.force(-1.0) == 1.35
    assert law.anisotropy == pytest.approx(3.0)
    assert np.isnan(law.force(0.0))


@pytest.mark.parametrize(
    ("fp", "fn", "word"), [(0.0, 1.0, "F_p"), (-1, 1, "F_p"), (1, 0.5, "F_n"), (np.nan, 1, "F_p")]
)
def test_bad_parameters_are_refused(fp, fn, word):
    with pytest.raises(InputError, match=word):
        DirectionalFriction(fp, fn)
