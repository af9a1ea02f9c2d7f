"""The texture-prediction example's design grid: what the comparison covers."""

import importlib.util
from pathlib import Path

from bristlecrawler.scenario.convert import to_spec

PATH = Path(__file__).resolve().parents[2] / "examples" / "texture_prediction.py"


def _example():
    spec = importlib.util.spec_from_file_location("texture_prediction", PATH)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_the_grid_covers_24_valid_designs_over_the_ranges():
    ex = _example()
    designs = ex.grid()
    assert len(set(designs)) == 24
    values = {}
    for d in designs:
        sc = ex.scenario(d)
        to_spec(sc).check()  # every design is a valid crawler
        for kv in d:
            key, v = kv.split("=")
            values.setdefault(key, set()).add(float(v))
    assert values["bristle.alpha_deg"] == {30, 45, 60}
    assert values["substrate.pitch"] == {1.5, 2, 3, 4}
    assert values["bristle.count"] == {2, 3, 4}
    assert min(values["actuation.s_max"]) >= 8 and max(values["actuation.s_max"]) <= 20
