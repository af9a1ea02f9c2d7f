"""The one adaptive step rule (:meth:`fe.StepControl.decide`) that every stepper uses:
the compiled loops trace it, the host loops call it on numbers; both must decide alike."""

import functools
import math

import jax
import jax.numpy as jnp
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from bristlecrawler.fe import StepControl
from bristlecrawler.fe.status import FATAL, STEP_ERROR, STEP_TOO_SMALL, SUCCESS, Status

STATUSES = [int(s) for s in Status if s != STEP_TOO_SMALL]


@functools.cache
def _traced(control, checked):
    def decide(s, i, h, r):
        return control.decide(s, i, h, 2 * h, 1e-6, 0.05, r if checked else None)

    return jax.jit(decide)


@settings(max_examples=60, deadline=None)
@given(
    status=st.sampled_from(STATUSES),
    iterations=st.integers(0, 30),
    h=st.floats(1e-7, 0.1),
    ratio=st.one_of(st.none(), st.floats(0.0, 3.0), st.just(math.nan)),
    grow=st.sampled_from([1.0, 1.5, 2.5]),
    easy=st.sampled_from([0, 4]),
)
def test_the_traced_rule_decides_as_the_rule_on_numbers(status, iterations, h, ratio, grow, easy):
    control = StepControl(grow, easy)
    host = control.decide(status, iterations, h, 2 * h, 1e-6, 0.05, ratio)
    r = jnp.asarray(0.0 if ratio is None else ratio)
    run = _traced(control, ratio is not None)
    out = run(jnp.asarray(status), jnp.asarray(iterations), jnp.asarray(h), r)
    assert (int(out.status), int(out.cause), bool(out.good), bool(out.failed)) == (
        host.status,
        host.cause,
        host.good,
        host.failed,
    )
    assert float(out.dt) == pytest.approx(host.dt, rel=1e-15)


@settings(max_examples=60, deadline=None)
@given(
    status=st.sampled_from(STATUSES),
    iterations=st.integers(0, 30),
    h=st.floats(1e-7, 0.1),
    ratio=st.one_of(st.none(), st.floats(0.0, 3.0)),
)
def test_a_step_is_accepted_grown_halved_or_ends_the_run_as_documented(
    status, iterations, h, ratio
):
    c, dt_min, dt_max = StepControl(), 1e-6, 0.05
    out = c.decide(status, iterations, h, h, dt_min, dt_max, ratio)
    checked_ok = ratio is None or ratio <= 1.0
    assert out.good == (status == SUCCESS and checked_ok)
    if out.good:
        easy = iterations <= c.easy_iterations and (ratio is None or ratio * c.grow**3 <= 1)
        assert out.dt == (min(h * c.grow, dt_max) if easy else h)
        assert not out.failed
        return
    assert out.dt == 0.5 * h
    assert out.cause == (STEP_ERROR if status == SUCCESS else status)
    assert out.failed == (status in FATAL or 0.5 * h < dt_min)
    if out.failed and status not in FATAL:
        assert out.status == STEP_TOO_SMALL
    else:
        assert out.status == out.cause


class _Info:
    def __init__(self, iterations):
        self.iterations = iterations


@settings(max_examples=60, deadline=None)
@given(
    limit=st.floats(0.01, 0.3),
    t_end=st.floats(0.5, 3.0),
    dt=st.floats(0.05, 1.0),
)
def test_the_host_loop_reaches_the_end_with_steps_the_rule_allows(limit, t_end, dt):
    """A step of the host loop converges (easily) exactly when it is at most ``limit``:
    the loop ends at t_end, every accepted step is at most ``limit``, after each failure
    it halves the step tried, and it never tries past the end."""
    from bristlecrawler.fe.control import march

    control = StepControl()

    def attempt(t, h):
        return t + h, _Info(2), SUCCESS if h <= limit else 3, None

    t, tried = 0.0, []
    for a in march(attempt, 0.0, 0.0, t_end, dt, 1e-9, dt, control):
        tried.append(a.h)
        assert a.h <= t_end - t + 1e-12
        if a.outcome.good:
            assert a.h <= limit
            t = a.new
        else:
            assert not a.outcome.failed
            assert a.outcome.dt == pytest.approx(0.5 * a.h)
    assert t == pytest.approx(t_end)
    # grows after easy steps, within dt
    assert max(tried) <= dt


def test_the_host_loop_stops_on_a_failure_below_dt_min_and_when_told():
    from bristlecrawler.fe.control import march

    def never(t, h):
        return t + h, _Info(12), 3, None

    tries = list(march(never, 0.0, 0.0, 1.0, 0.1, 0.01, 0.1))
    # 0.1, 0.05, 0.025, 0.0125: half of the last is below dt_min, and the run ends
    assert [a.h for a in tries] == pytest.approx([0.1, 0.05, 0.025, 0.0125])
    assert tries[-1].outcome.failed and tries[-1].outcome.status == STEP_TOO_SMALL

    def fine(t, h):
        return t + h, _Info(1), SUCCESS, None

    rows = []
    for a in march(fine, 0.0, 0.0, 1.0, 0.1, 0.01, 0.1, more=lambda: len(rows) < 3):
        rows.append(a.h)
    # asked before each try: three steps of the ten to the end
    assert rows == pytest.approx([0.1, 0.1, 0.1])
