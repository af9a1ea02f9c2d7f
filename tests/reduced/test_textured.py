"""The reduced crawler on a texture against the paper's model, ratchets and the
Prandtl-Tomlinson small-pitch limit."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from bristlecrawler.errors import InputError
from bristlecrawler.reduced import (
    ReducedCrawler,
    Sin2Stroke,
    TriangleStroke,
    peristaltic,
    simulate,
)
from bristlecrawler.reduced.textured import TexturedCrawler
from bristlecrawler.reduced.textured_pair import PairBatch, pair_cycles
from bristlecrawler.results.texture import TextureLaw


def _random_law(rng, pitch=2.0, cells=8, k=0.5, wall=True):
    fp = rng.uniform(0.2, 0.5, cells)
    fn = rng.uniform(0.1, 0.8, cells)
    if wall:
        fn[rng.integers(cells)] = np.inf
    return TextureLaw(pitch, fp, fn, k, origin_mm=rng.uniform(0, pitch), tip_offset_mm=-3.3)


@pytest.mark.parametrize("n", [2, 3, 4])
def test_a_constant_law_is_the_papers_model(n):
    """One resistance per direction at every position: the same trajectories, forces,
    work and dissipation as the paper's solver, to round-off."""
    paper = ReducedCrawler.uniform(n, fp=0.3, k=0.5, fn=0.9)
    textured = TexturedCrawler.uniform(TextureLaw.constant(0.3, 0.9, 0.5, pitch=1.7), n)
    gait = peristaltic(TriangleStroke(6.0, 20.0), n - 1, 5.0) if n > 2 else Sin2Stroke(6.0, 20.0)
    ref = simulate(paper, gait, cycles=2, samples_per_cycle=300)
    got = simulate(textured, gait, cycles=2, samples_per_cycle=300)
    np.testing.assert_allclose(got.X, ref.X, atol=1e-10)
    np.testing.assert_allclose(got.x, ref.x, atol=1e-10)
    np.testing.assert_allclose(got.work, ref.work, atol=1e-10)
    np.testing.assert_allclose(got.dissipation, ref.dissipation, atol=1e-10)
    np.testing.assert_allclose(got.force, ref.force, atol=1e-10)


@settings(max_examples=8)
@given(
    pitch=st.floats(0.5, 4.0),
    s_max=st.floats(3.0, 20.0),
    k=st.floats(0.3, 3.0),
    cells=st.integers(1, 6),
    start=st.floats(0.0, 4.0),
)
def test_a_ratchet_moves_each_tip_and_the_body_by_whole_pitches(pitch, s_max, k, cells, start):
    """A sawtooth (weak backwards, one wall per pitch): a tip pulled back slides to the wall
    behind it, so after the first cycle every cycle moves the rear tip, and the crawler, by
    a whole number of pitches, and never more than the stroke."""
    fp = 0.2
    law = TextureLaw.sawtooth(pitch, fp, k, cells=cells)
    crawler = TexturedCrawler.uniform(law, 2, length=60.0, start=start)
    adv, _ = pair_cycles(PairBatch.of([law], 60.0, s_max, start), cycles=4)
    steady = adv[0, 1:]
    assert np.allclose(steady / pitch, np.round(steady / pitch), atol=1e-9)
    assert np.all(steady <= s_max + 1e-9)
    r = simulate(crawler, Sin2Stroke(s_max, 20.0), cycles=3, samples_per_cycle=20)
    rear = np.diff(r.x[r.cycle_bounds, 0])[1:]
    assert np.allclose(rear / pitch, np.round(rear / pitch), atol=1e-9)
    np.testing.assert_allclose(r.per_cycle()[0], adv[0, :3], atol=1e-9)


def test_the_two_bristle_batch_is_the_event_solver():
    """The batch of two-bristle designs (turning points only) and the event-driven
    solver (sampled strokes) give the same advance and work, cycle by cycle."""
    rng = np.random.default_rng(7)
    laws = [_random_law(rng) for _ in range(4)]
    s_max = [5.0, 8.0, 12.0, 17.0]
    adv, work = pair_cycles(PairBatch.of(laws, 100.0, s_max, 0.3), cycles=3)
    for j, law in enumerate(laws):
        crawler = TexturedCrawler.uniform(law, 2, start=0.3)
        r = simulate(crawler, Sin2Stroke(s_max[j], 20.0), cycles=3, samples_per_cycle=40)
        a, w = r.per_cycle()
        np.testing.assert_allclose(a, adv[j], atol=1e-9)
        np.testing.assert_allclose(w, work[j], atol=1e-9)
        assert r.energy_balance_error < 1e-12


@settings(max_examples=4, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), cells=st.integers(2, 7))
def test_each_design_of_a_batch_moves_as_it_would_alone(seed, cells):
    """Designs of a batch finish their cycles after different numbers of events; each
    one's advance and work are those of the design alone in a batch and, for one of
    them, those of the event-driven solver (rear and front laws of their own)."""
    rng = np.random.default_rng(seed)
    B = 20

    def law(pitch, origin):
        fn = rng.uniform(0.1, 0.8, cells)
        fn[rng.integers(cells)] = np.inf if rng.random() < 0.5 else fn[0]
        return TextureLaw(
            pitch,
            rng.uniform(0.2, 0.5, cells),
            fn,
            rng.uniform(0.3, 3.0),
            origin_mm=origin,
            tip_offset_mm=rng.uniform(-4.0, 0.0),
        )

    pitch, origin = rng.uniform(0.5, 4.0, B), rng.uniform(0.0, 4.0, B)
    pairs = [(law(pitch[j], origin[j]), law(pitch[j], origin[j])) for j in range(B)]
    length = rng.uniform(40.0, 120.0, B)
    s_max = length * rng.uniform(0.05, 0.3, B)
    start = rng.uniform(0.0, 3.0, B)
    adv, work = pair_cycles(PairBatch.of(pairs, length, s_max, start), cycles=3)
    for j in range(B):
        a, w = pair_cycles(PairBatch.of([pairs[j]], length[j], s_max[j], start[j]), cycles=3)
        np.testing.assert_allclose(a[0], adv[j], atol=1e-9)
        np.testing.assert_allclose(w[0], work[j], atol=1e-9)
    j = rng.integers(B)
    crawler = TexturedCrawler(pairs[j], [length[j]], start[j])
    r = simulate(crawler, Sin2Stroke(s_max[j], 20.0), cycles=3, samples_per_cycle=40)
    a, w = r.per_cycle()
    np.testing.assert_allclose(a, adv[j], atol=1e-9)
    np.testing.assert_allclose(w, work[j], atol=1e-9)


@pytest.mark.parametrize("n", [2, 3])
def test_work_is_elastic_energy_plus_friction_plus_snaps(n):
    """Every snap's loss is the elastic energy it releases: W = E_el + D to round-off."""
    rng = np.random.default_rng(n)
    crawler = TexturedCrawler.uniform(_random_law(rng), n)
    r = simulate(crawler, Sin2Stroke(9.0, 20.0), cycles=2, samples_per_cycle=80)
    assert r.energy_balance_error < 1e-12
    assert np.all(np.diff(r.dissipation) >= -1e-12)


def test_the_small_pitch_limit_is_the_papers_law_at_the_largest_resistances():
    """Prandtl-Tomlinson limit (Gidoni & DeSimone, arXiv 1602.05611): as the pitch of a
    texture goes to zero at a fixed profile, a sliding tip must pass every cell's
    resistance and snaps through the rest, so the crawler tends to the paper's model with
    F_p = max F_p(x) and F_n = max F_n(x); the gap closes with the pitch."""
    rng = np.random.default_rng(3)
    fp, fn, k, s_max = rng.uniform(0.2, 0.5, 6), rng.uniform(0.3, 1.2, 6), 0.5, 4.0
    paper = ReducedCrawler.two_bristle(k=k, fp=fp.max(), fn=fn.max(), length=50.0)
    ref = simulate(paper, Sin2Stroke(s_max, 20.0), cycles=2, samples_per_cycle=200)
    ref_adv, ref_work = ref.per_cycle()
    gaps = []
    for pitch in (0.2, 0.05, 0.0125):
        law = TextureLaw(pitch, fp, fn, k)
        adv, work = pair_cycles(PairBatch.of([law], 50.0, s_max), cycles=2)
        gaps.append(np.abs(adv[0] - ref_adv).max())
        assert np.abs(adv[0] - ref_adv).max() <= 2 * pitch
        np.testing.assert_allclose(work[0], ref_work, rtol=5 * pitch)
    assert gaps[-1] < gaps[0]


def test_laws_refuse_what_is_not_a_resistance():
    with pytest.raises(InputError, match="F_p"):
        TextureLaw(2.0, [0.2, -0.1], [0.3, 0.3], 1.0)
    with pytest.raises(InputError, match="F_n"):
        TextureLaw(2.0, [0.2, 0.1], [0.3], 1.0)
    with pytest.raises(InputError, match="F_p"):
        TextureLaw(2.0, [np.inf], [0.3], 1.0)
    with pytest.raises(InputError, match="pitch"):
        TextureLaw(0.0, [0.2], [0.3], 1.0)
    with pytest.raises(InputError, match="edges"):
        TextureLaw(2.0, [0.2, 0.2], [0.3, 0.3], 1.0, walls_mm=(0.5,))
    law = TextureLaw.sawtooth(2.0, 0.2, 1.0, cells=4)
    back = TextureLaw.from_dict(law.to_dict())
    np.testing.assert_array_equal(back.fn_N, law.fn_N)
    assert back.walls_mm == law.walls_mm == (0.0,)
    np.testing.assert_allclose(law.lock_positions_mm, [0.0])
    assert law.backward_resistance(4.0) == np.inf and law.backward_resistance(4.1) == 0.1


def test_from_drag_builds_either_model():
    law = TextureLaw.sawtooth(2.0, 0.2, 1.0, cells=4, fn=0.1)
    summary = {"k_N_per_mm": 1.0, "fp_N": 0.2, "fn_N": 0.3, "texture": law.to_dict()}
    paper = ReducedCrawler.from_drag(summary, 3)
    textured = TexturedCrawler.from_drag(summary, 3, start_mm=1.0)
    assert isinstance(paper, ReducedCrawler) and isinstance(textured, TexturedCrawler)
    assert textured.n_bristles == 3 and textured.start_mm == 1.0
    with pytest.raises(InputError, match="texture"):
        TexturedCrawler.from_drag({k: summary[k] for k in ("k_N_per_mm", "fp_N")})
    with pytest.raises(InputError, match="paper or texture"):
        ReducedCrawler.from_drag(summary, model="fe")


def test_from_drag_with_model_texture_still_builds_the_textured_crawler():
    law = TextureLaw.sawtooth(2.0, 0.2, 1.0, cells=4, fn=0.1)
    summary = {"k_N_per_mm": 1.0, "fp_N": 0.2, "fn_N": 0.3, "texture": law.to_dict()}
    with pytest.warns(DeprecationWarning, match="TexturedCrawler.from_drag"):
        old = ReducedCrawler.from_drag(summary, 3, model="texture", start_mm=1.0)
    new = TexturedCrawler.from_drag(summary, 3, start_mm=1.0)
    assert [a.to_dict() for a in old.laws] == [b.to_dict() for b in new.laws]
    assert old.start_mm == new.start_mm
    np.testing.assert_array_equal(old.segment_lengths, new.segment_lengths)
