"""The exact incremental solver against closed forms, invariances and balance laws."""

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from bristlecrawler.errors import InputError
from bristlecrawler.reduced import (
    ReducedCrawler,
    SampledStroke,
    Sin2Stroke,
    TriangleStroke,
    breathing,
    closed_form,
    peristaltic,
    simulate,
    solve,
)

# F_p/k as a fraction of s~ covering the three regimes: <1/4 (3), 1/4..1/2 (2), >1/2 (1).
c_fraction = st.floats(0.005, 0.8)


def _compare_with_closed_form(s_max, c, k, cycles, samples, stroke_cls=Sin2Stroke):
    fp = c * k
    crawler = ReducedCrawler.two_bristle(k=k, fp=fp, fn=2.5 * fp, length=s_max * 3)
    stroke = stroke_cls(s_max, 20.0)
    res = simulate(crawler, stroke, cycles, samples)
    n, up = closed_form.branches(res.t, 20.0)
    ref = closed_form.trajectory(stroke(res.t), n, up, s_max, fp, k)
    return res, ref


@given(
    s_max=st.floats(1.0, 40.0),
    frac=c_fraction,
    k=st.floats(0.05, 5.0),
    cycles=st.integers(1, 4),
    samples=st.integers(2, 300),
)
def test_solver_reproduces_closed_form_at_every_sample(s_max, frac, k, cycles, samples):
    c = frac * s_max
    res, ref = _compare_with_closed_form(s_max, c, k, cycles, samples)
    assert np.max(np.abs(res.delta - ref.delta)) < 1e-9
    assert np.max(np.abs(res.force - ref.force)) < 1e-9 * max(1.0, c * k)
    assert np.max(np.abs(res.work - ref.work)) < 1e-9 * max(1.0, ref.work.max())
    # States agree except at samples sitting exactly on a transition shortening.
    s = res.shortening[:, 0]
    near = np.min(np.abs(s[:, None] - np.array([2 * c, 4 * c, s_max - 4 * c])), axis=1) < 1e-9
    assert np.all((res.state == ref.state).all(axis=1) | near)
    assert res.net_advance == pytest.approx(
        float(closed_form.net_advance(s_max, c, cycles)), abs=1e-9
    )


@pytest.mark.parametrize("frac", [0.0475, 0.3, 0.6])  # one case per regime
def test_triangle_and_sin2_strokes_give_the_same_gait(frac):
    s_max, k = 20.0, 0.48
    a, _ = _compare_with_closed_form(s_max, frac * s_max, k, 3, 400, Sin2Stroke)
    b, _ = _compare_with_closed_form(s_max, frac * s_max, k, 3, 250, TriangleStroke)
    # Rate independence: per-cycle advance and work, and Delta at turning points, coincide
    # although the two strokes are sampled at different shortenings and speeds.
    for x, y in zip(a.per_cycle(), b.per_cycle(), strict=True):
        np.testing.assert_allclose(x, y, atol=1e-9)
    turn_a = a.delta[np.isin(a.t, np.arange(0, 61, 10.0))]
    turn_b = b.delta[np.isin(b.t, np.arange(0, 61, 10.0))]
    np.testing.assert_allclose(turn_a, turn_b, atol=1e-9)


@given(warp=st.lists(st.floats(0.05, 5.0), min_size=1, max_size=1))
def test_time_reparametrisation_changes_nothing_but_event_times(warp):
    crawler = ReducedCrawler.two_bristle()
    stroke = Sin2Stroke(20.0, 20.0)
    t = stroke.sample_times(2, 200)
    s = stroke(t)
    t2 = t * warp[0] + 0.3 * np.sin(t / 40.0 * np.pi) ** 2  # a monotone warp of time
    r1 = solve(crawler, t, s)
    r2 = solve(crawler, t2, s)
    np.testing.assert_array_equal(r1.delta, r2.delta)
    np.testing.assert_array_equal(r1.state, r2.state)
    assert len(r1.events) == len(r2.events)


def _play_reference(s_path, c):
    """Independent two-bristle reference: the left spring elongation is the stop operator of
    s/2 with bounds +-c; the left tip slides by ds while it is at +c and s grows, the right
    tip by -ds while it is at -c and s decreases. Evaluated on a very fine path."""
    e, x1, out = 0.0, 0.0, []
    for ds in np.diff(s_path):
        trial = e + 0.5 * ds
        if trial > c:
            x1 += 2 * (trial - c)
            trial = c
        elif trial < -c:
            trial = -c
        e = trial
        out.append(x1 + e)
    return np.concatenate([[0.0], np.array(out) - s_path[1:] + s_path[0]])


def test_non_monotone_history_against_stop_operator_reference():
    knots_t = np.array([0.0, 1.0, 2.0, 3.0, 4.0])
    knots_s = np.array([0.0, 15.0, 5.0, 20.0, 0.0])
    crawler = ReducedCrawler.two_bristle()
    res = simulate(crawler, SampledStroke(knots_t, knots_s))
    fine_t = np.linspace(0, 4, 400_001)
    fine_s = np.interp(fine_t, knots_t, knots_s)
    ref = _play_reference(fine_s, crawler.fp[0] / crawler.k[0])
    np.testing.assert_allclose(res.delta, ref[::100_000], atol=1e-9)
    # Stick/slip along that history: left slides on the way up, right on the way down.
    np.testing.assert_array_equal(res.state[1:], [[1, 0], [0, 1], [1, 0], [0, 1]])


@given(
    n=st.integers(2, 7),
    seed=st.integers(0, 2**31),
    ratio=st.sampled_from([1.0, 1.0 + 1e-6, 1.05, 2.0, 5.0]),
)
def test_general_crawler_obeys_friction_law_and_energy_balance(n, seed, ratio):
    rng = np.random.default_rng(seed)
    k = rng.uniform(0.1, 2.0, n)
    fp = rng.uniform(0.1, 1.0, n)
    seg = rng.uniform(20.0, 60.0, n - 1)
    crawler = ReducedCrawler(k=k, fp=fp, fn=ratio * fp, segment_lengths=seg)
    m = 60
    t = np.cumsum(rng.uniform(0.1, 1.0, m))
    s = rng.uniform(0, 1, (m, n - 1)) * 0.9 * seg
    s[0] = 0.0
    res = solve(crawler, t, s)
    f = res.force
    tol = 1e-9
    assert res.energy_balance_error < 1e-9
    assert np.max(np.abs(f.sum(axis=1))) < tol  # global balance, eq. (4.3)
    assert np.all(f >= -fp - tol) and np.all(f <= ratio * fp + tol)
    dx = np.diff(res.x, axis=0)
    st_ = res.state[1:]
    # On intervals without an event inside, stuck tips do not move and sliding tips move in
    # the direction of their state; a tip still sliding at a sample is at yield there.
    inside = [e.t for e in res.events if not np.any(np.isclose(e.t, t, rtol=0, atol=1e-12))]
    clean = np.ones(m - 1, bool)
    clean[np.searchsorted(t, inside) - 1] = False
    assert np.all(np.abs(dx[clean][st_[clean] == 0]) < tol)
    assert np.all((dx * st_)[clean] >= -tol)
    assert np.all(np.isclose(res.force[1:], -fp, atol=tol)[st_ == 1])
    assert np.all(np.isclose(res.force[1:], ratio * fp, atol=tol)[st_ == -1])
    # Over any interval a tip moves forwards only after reaching forward yield (its work
    # is dissipated): the total dissipation bounds the slips weighted by F_p.
    assert np.sum(np.abs(dx) * fp) <= res.dissipation[-1] + tol
    assert np.all(np.diff(res.dissipation) >= -tol)


def test_refining_the_sampling_does_not_change_the_samples():
    rng = np.random.default_rng(3)
    crawler = ReducedCrawler.uniform(4, length=150.0, fn=1.3 * 0.456)
    t = np.arange(40.0)
    s = rng.uniform(0, 20, (40, 3))
    s[0] = 0
    coarse = solve(crawler, t, s)
    tf = np.linspace(0, 39, 39 * 7 + 1)
    sf = np.stack([np.interp(tf, t, s[:, j]) for j in range(3)], axis=1)
    fine = solve(crawler, tf, sf)
    np.testing.assert_allclose(fine.X[::7], coarse.X, atol=1e-9)
    np.testing.assert_allclose(fine.x[::7], coarse.x, atol=1e-9)
    np.testing.assert_allclose(fine.work[::7], coarse.work, atol=1e-9)
    ev_c = [(round(e.t, 9), e.bristle, e.after) for e in coarse.events]
    ev_f = [(round(e.t, 9), e.bristle, e.after) for e in fine.events]
    assert ev_c == ev_f


def test_symmetric_friction_gives_no_net_motion_and_mirror_symmetry():
    crawler = ReducedCrawler.two_bristle(fn=0.456)  # F_n = F_p: the alpha = 0 analogue
    res = simulate(crawler, Sin2Stroke(20.0, 20.0), 5, 400)
    assert abs(res.net_advance) < 1e-12
    np.testing.assert_allclose(res.delta, -res.rear_displacement, atol=1e-12)
    assert res.dissipation[-1] > 0


def test_peristaltic_with_zero_lag_is_breathing():
    crawler = ReducedCrawler.uniform(4, length=120.0)
    stroke = Sin2Stroke(15.0, 20.0)
    a = simulate(crawler, breathing(stroke, 3), 3, 200)
    b = simulate(crawler, peristaltic(stroke, 3, 0.0), 3, 200)
    np.testing.assert_array_equal(a.delta, b.delta)


def test_peristaltic_wave_direction_sets_the_difference():
    # With isotropic-enough friction a peristaltic wave moves the crawler against the wave.
    crawler = ReducedCrawler.uniform(5, length=200.0, fn=1.0 * 0.456)
    stroke = Sin2Stroke(15.0, 20.0)
    fwd = simulate(crawler, peristaltic(stroke, 4, 5.0), 4, 400)
    bwd = simulate(crawler, peristaltic(stroke, 4, -5.0), 4, 400)
    assert fwd.energy_balance_error < 1e-9 and bwd.energy_balance_error < 1e-9
    assert fwd.net_advance == pytest.approx(-bwd.net_advance, abs=1e-9)
    assert abs(fwd.net_advance) > 1.0


@pytest.mark.parametrize(
    ("kwargs", "word"),
    [
        ({"k": 0.0}, "k"),
        ({"fp": -1.0}, "F_p"),
        ({"fn": 0.1}, "F_n"),
        ({"n_bristles": 1}, "2 bristles"),
    ],
)
def test_bad_crawlers_are_refused(kwargs, word):
    with pytest.raises(InputError, match=word):
        ReducedCrawler.uniform(**kwargs)


def test_stroke_longer_than_the_body_is_refused():
    with pytest.raises(InputError, match="smaller than the segment length"):
        simulate(ReducedCrawler.two_bristle(), Sin2Stroke(100.0, 20.0), 1)


@pytest.mark.parametrize(
    ("t", "s", "word"),
    [
        ([0, 2, 1], [0, 1, 2], "increasing"),
        ([0, 1, 2], [0, np.nan, 1], "non-finite"),
        ([0, 1], [0, -1], ">= 0"),
        ([0, np.inf], [0, 1], "non-finite time"),
    ],
)
def test_bad_histories_are_refused(t, s, word):
    with pytest.raises(InputError, match=word):
        SampledStroke(np.array(t, float), np.array(s, float))
