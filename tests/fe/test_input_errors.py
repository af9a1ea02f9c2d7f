"""Bad input is refused with one-line InputError naming the parameter, before solving."""

import pytest

from bristlecrawler.errors import InputError
from bristlecrawler.fe import Structure, TaperedRect, solve_static

SEC = TaperedRect(E=1.0, b=1.0, h0=0.1)


@pytest.mark.parametrize(
    ("field", "value"), [("E", 0.0), ("E", -1.0), ("b", 0.0), ("h0", -0.1), ("h1", 0.0)]
)
def test_non_positive_section(field, value):
    kw = {"E": 1.0, "b": 1.0, "h0": 0.1, "h1": 0.1, field: value}
    s = Structure()
    with pytest.raises(InputError, match=field):
        s.chain((0.0, 0.0), (1.0, 0.0), 2, TaperedRect(**kw))


def test_zero_length_element():
    s = Structure()
    a, b = s.node(0.0, 0.0), s.node(0.0, 0.0)
    s.beam(a, b, SEC)
    with pytest.raises(InputError, match="zero length"):
        s.build()


def test_disconnected():
    s = Structure()
    s.chain((0.0, 0.0), (1.0, 0.0), 2, SEC)
    s.chain((5.0, 0.0), (6.0, 0.0), 2, SEC)
    with pytest.raises(InputError, match="disconnected"):
        s.build()


def test_conflicting_constraints():
    s = Structure()
    n = s.chain((0.0, 0.0), (1.0, 0.0), 2, SEC)
    s.fix(n[0])
    with pytest.raises(InputError, match="prescribed twice"):
        s.fix(n[0], "x")
    s.rigid_link(n[1], n[0])
    with pytest.raises(InputError, match="two rigid links"):
        s.rigid_link(n[1], n[2])
    s2 = Structure()
    m = s2.chain((0.0, 0.0), (1.0, 0.0), 2, SEC)
    s2.fix(m[2], "y")
    s2.rigid_link(m[2], m[0])
    with pytest.raises(InputError, match="conflicting"):
        s2.build()


def test_link_cycle():
    s = Structure()
    n = s.chain((0.0, 0.0), (1.0, 0.0), 2, SEC)
    s.rigid_link(n[1], n[0])
    s.rigid_link(n[0], n[1])
    with pytest.raises(InputError, match="cycle"):
        s.build()


def test_under_constrained_static():
    s = Structure()
    n = s.chain((0.0, 0.0), (1.0, 0.0), 3, SEC)
    s.fix(n[0], ("x", "y"))  # pinned: the beam can still rotate about the pin
    s.load(n[-1], fy=1e-3)
    with pytest.raises(InputError, match="under-constrained"):
        solve_static(s.build())


def test_error_is_one_line():
    with pytest.raises(InputError) as exc:
        TaperedRect(E=-2.0, b=1.0, h0=1.0).check()
    assert "\n" not in str(exc.value)
