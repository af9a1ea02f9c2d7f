"""The results layer: one typed result per kind of output, whatever the model, with its
JSON keys spelled in one file."""

import dataclasses
import math
import pathlib
import re

import numpy as np
import pytest

import bristlecrawler
from bristlecrawler.errors import InputError
from bristlecrawler.results import DragSummary, RunMetrics, RunSummary, keys, summary_of

SRC = pathlib.Path(bristlecrawler.__file__).parent

#: The result keys every model writes: spelled only in results/keys.py.
CORE_KEYS = (
    keys.NET_ADVANCE_MM,
    keys.ADVANCE_PER_CYCLE_MM,
    keys.WORK_MJ,
    keys.WORK_PER_CYCLE_MJ,
    keys.COST_OF_TRANSPORT,
    keys.MAX_ABS_CONNECTOR_FORCE_N,
    keys.K_N_PER_MM,
    keys.FP_N,
    keys.FN_N,
)


def test_each_result_key_is_spelled_in_one_source_file():
    spelled = {}
    for path in SRC.rglob("*.py"):
        text = path.read_text(encoding="utf-8")
        for key in CORE_KEYS:
            # (a field of the same name set in __post_init__ is an attribute, not a key)
            if re.search(rf"(?<!__setattr__\(self, )[\"']{re.escape(key)}[\"']", text):
                spelled.setdefault(key, []).append(str(path.relative_to(SRC)))
    assert spelled == {key: ["results/keys.py"] for key in CORE_KEYS}


def _summary(**changes):
    fields = {
        f.name: 1.0
        for f in dataclasses.fields(RunSummary)
        if f.name not in ("scenario", "metrics", "warnings")
    }
    fields |= {"bristles": 2, "steps": 10, "newton_iterations": 30, "rejected_steps": 1}
    fields |= {"work_per_cycle": (3.0, 4.0)}
    base = RunSummary(scenario="s", metrics=RunMetrics(2.0, (1.0, 1.0), 7.0), **fields)
    return dataclasses.replace(base, **changes)


def test_a_run_summary_writes_its_metrics_under_the_shared_keys():
    d = _summary().to_dict()
    assert (d[keys.NET_ADVANCE_MM], d[keys.ADVANCE_PER_CYCLE_MM], d[keys.WORK_MJ]) == (
        2.0,
        [1.0, 1.0],
        7.0,
    )
    assert d[keys.WORK_PER_CYCLE_MJ] == [3.0, 4.0] and d["warnings"] == []
    assert RunMetrics.from_dict(d) == _summary().metrics
    assert list(d)[:5] == ["scenario", "bristles", *_summary().metrics.to_dict()]


def test_warnings_added_to_a_run_summary_follow_its_own():
    s = _summary(warnings=("a",)).with_warnings(["b", "c"])
    assert s.warnings == ("a", "b", "c") and s.to_dict()["warnings"] == ["a", "b", "c"]


def _drag_mapping():
    return {keys.K_N_PER_MM: 0.5, keys.FP_N: 0.25, keys.FN_N: 0.4, "texture": None}


class _Result:
    def summary(self):
        return _drag_mapping()


class _Summarizing:
    def summarize(self):
        return DragSummary.from_dict(_drag_mapping())


@pytest.mark.parametrize(
    "drag",
    [_drag_mapping(), _Result(), _Summarizing(), DragSummary.from_dict(_drag_mapping())],
    ids=["mapping", "summary()", "summarize()", "typed"],
)
def test_whatever_a_drag_test_is_given_as_it_is_read_as_one_type(drag):
    s = summary_of(drag)
    assert isinstance(s, DragSummary)
    assert (s.k, s.fp, s.fn) == (0.5, 0.25, 0.4)
    assert math.isnan(s.settle_creep) and s.texture is None


def test_something_else_is_not_a_drag_summary():
    with pytest.raises(InputError, match="not a drag test's summary: ndarray"):
        summary_of(np.zeros(3))
