"""Run folders' configuration files are strict JSON."""

import json
import math

from bristlecrawler.io.runs import claim_run_dir, json_safe


def _strict(text):
    def refuse(name):
        raise ValueError(f"not JSON: {name}")

    return json.loads(text, parse_constant=refuse)


def test_config_json_has_no_infinity(tmp_path):
    config = {"solver": {"energy_loss_tol": math.inf, "dt": 0.05}, "x": [-math.inf, 1.0]}
    with claim_run_dir(tmp_path / "run", "test") as run:
        run.write_metadata(config, "test")
    cfg = _strict((tmp_path / "run" / "config.json").read_text())
    assert cfg == {"solver": {"energy_loss_tol": "inf", "dt": 0.05}, "x": ["-inf", 1.0]}
    assert float(cfg["solver"]["energy_loss_tol"]) == math.inf
    assert json_safe(math.nan) == "nan"
