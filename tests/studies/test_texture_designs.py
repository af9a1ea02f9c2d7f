"""Reduced designs on a texture law in a study: the exact solver, design by design."""

import json

import numpy as np

from bristlecrawler.results.texture import TextureLaw
from bristlecrawler.scenario.reduced import ReducedConfig
from bristlecrawler.studies.evaluate import evaluate_reduced_chunk


def test_a_constant_texture_law_gives_the_closed_forms_designs(tmp_path):
    """``texture`` in a reduced study's base: the designs run on the law; a law constant
    over the pitch gives what the paper's closed forms give for its F_p, F_n and k."""
    law = tmp_path / "summary.json"
    law.write_text(json.dumps({"texture": TextureLaw.constant(0.456, 1.368, 0.48).to_dict()}))
    base = ReducedConfig().model_dump() | {"cycles": 2, "samples_per_cycle": 100}
    s = {"s_max": np.array([0.5, 8.0, 20.0])}
    textured = evaluate_reduced_chunk(base | {"texture": str(law)}, s)
    closed = evaluate_reduced_chunk(base, s)
    assert np.all(textured["status"] == closed["status"])
    for key in ("net_advance_mm", "last_cycle_advance_mm", "work_mJ"):
        np.testing.assert_allclose(textured[key], closed[key], rtol=1e-9, atol=1e-9)
