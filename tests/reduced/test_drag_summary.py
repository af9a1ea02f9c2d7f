"""The drag test's summary as a typed result: the keys of its summary.json, read back
exactly, and fed to the reduced crawler as the mapping is."""

import json
import math

import pytest

from bristlecrawler.io.jsonio import dumps_strict
from bristlecrawler.reduced import ReducedCrawler
from bristlecrawler.reduced.textured import TexturedCrawler
from bristlecrawler.results.drag import DragSummary, Sliding
from bristlecrawler.results.texture import TextureLaw

#: The keys of a drag test's summary.json that slid both ways (before the typed result).
BOTH_WAYS = [
    "k_N_per_mm",
    "k_unload_N_per_mm",
    "k_initial_N_per_mm",
    "fp_N",
    "fp_scatter_N",
    "fp_range_N",
    "fp_peak_N",
    "fp_pitches",
    "fn_N",
    "fn_scatter_N",
    "fn_range_N",
    "fn_peak_N",
    "fn_pitches",
    "fp_over_k_mm",
    "mu_load_N",
    "load_N",
    "dissipation_mJ_per_mm",
    "energy_balance_rel_error",
    "steps",
    "newton_iterations",
    "wall_time_s",
    "texture",
    "settle_speed_mm_s",
    "settle_creep_mm",
]


def _summary(against=True, texture=True) -> DragSummary:
    return DragSummary(
        k=0.8,
        k_unload=0.79,
        k_initial=0.81,
        along=Sliding(0.2, 0.01, 0.19, 0.21, 0.3, 4),
        against=Sliding(0.5, 0.02, 0.48, 0.52, 0.6, 3) if against else None,
        mu_load=0.5,
        load=1.0,
        dissipation_per_mm=0.35,
        energy_balance_rel_error=1e-4,
        steps=400,
        newton_iterations=900,
        wall_time=12.5,
        texture=TextureLaw.sawtooth(2.0, 0.2, 0.8, cells=4) if texture else None,
    )


def test_the_keys_are_those_of_the_summary_file():
    assert list(_summary().to_dict()) == BOTH_WAYS
    # A direction that never slid writes its mean, scatter and peak as NaN, nothing more.
    one_way = _summary(against=False, texture=False).to_dict()
    assert [k for k in BOTH_WAYS if k not in one_way] == ["fn_range_N", "fn_pitches"]
    assert math.isnan(one_way["fn_N"]) and one_way["texture"] is None


@pytest.mark.parametrize("against", [True, False])
def test_the_summary_reads_back_from_its_json_file(against):
    s = _summary(against=against, texture=against)
    text = dumps_strict(s.to_dict())
    back = DragSummary.from_dict(json.loads(text))
    assert dumps_strict(back.to_dict()) == text
    assert back.fp == 0.2 and back.fp_over_k == pytest.approx(0.25)
    assert back.against == s.against


def test_the_reduced_crawler_takes_the_typed_summary_as_its_mapping():
    s = _summary()
    typed = ReducedCrawler.from_drag(s, 3)
    mapping = ReducedCrawler.from_drag(json.loads(dumps_strict(s.to_dict())), 3)
    assert (typed.k[0], typed.fp[0], typed.fn[0]) == (0.8, 0.2, 0.5)
    assert (mapping.k[0], mapping.fp[0], mapping.fn[0]) == (0.8, 0.2, 0.5)
    textured = TexturedCrawler.from_drag(s, 3)
    assert textured.laws[0] is s.texture
