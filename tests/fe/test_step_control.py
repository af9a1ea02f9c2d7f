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
