"""``bristlecrawler predict``: the bristled model by default, the drag-test models beside it
from a (cached) drag test, bad input."""

import json
from pathlib import Path

import numpy as np
import pytest

from bristlecrawler.io.jsonio import dumps_strict
from bristlecrawler.jobs import predict
from bristlecrawler.jobs.drag import DragRun
from bristlecrawler.results.texture import TextureLaw
from bristlecrawler.scenario.convert import to_spec
from bristlecrawler.scenario.load import load_scenario

K, FP, FN = 1.2, 0.22, 0.5


@pytest.fixture(autouse=True)
def _quick_bristled(request, monkeypatch):
    """The bristled model's seconds-long run is not what the drag-cache tests are about."""
    if "bristled" in request.node.name:
        return
    quick = {"net_advance_mm": 1.0, "advance_per_cycle_mm": [1.0], "work_mJ": 1.0}
    monkeypatch.setattr(predict, "bristled_result", lambda spec, cycles: (quick, None))


@pytest.mark.slow
def test_the_bristled_model_is_the_default_and_needs_no_drag_test(monkeypatch, run_cli):
    monkeypatch.setattr("bristlecrawler.jobs.drag.run_drag", _no_drag)
    argv = ["predict", "--set", "actuation.s_max=4", "--cycles", "1", "--no-drag", "--json"]
    code, out, _ = run_cli(argv)
    assert code == 0
    r = json.loads(out)
    assert r["default"] == "bristled"
    assert r["bristled"]["advance_per_cycle_mm"][0] > 0.5
    assert r["texture"] is None and r["paper"] is None and r["drag"] is None
    assert "drag test" in r["models"]["texture"]["not_run"]
    assert "docs/findings.md" in r["models"]["bristled"]["checked"]


def _summary(law: TextureLaw) -> dict:
    return {"k_N_per_mm": K, "fp_N": FP, "fn_N": FN, "texture": law.to_dict()}


def _entry(tmp_path, monkeypatch) -> Path:
    monkeypatch.setenv("BRISTLECRAWLER_DRAG_CACHE", str(tmp_path / "cache"))
    sc = load_scenario("paper")
    key = predict.cache_key(sc, predict.prediction_drag_test(to_spec(sc)))
    return tmp_path / "cache" / f"{key}.json"


def _no_drag(*args, **kwargs):
    raise AssertionError("a drag test ran")


def test_a_constant_law_predicts_what_the_papers_model_does(tmp_path, monkeypatch, run_cli):
    """From the cache, no drag test: with a law constant over the pitch the texture model
    is the paper's model (same advance per cycle and work)."""
    path = _entry(tmp_path, monkeypatch)
    path.parent.mkdir(parents=True)
    law = TextureLaw.constant(FP, FN, K, pitch=2.0)
    path.write_text(dumps_strict({"version": predict.CACHE_VERSION, "summary": _summary(law)}))
    monkeypatch.setattr("bristlecrawler.jobs.drag.run_drag", _no_drag)
    code, out, _ = run_cli(["predict", "--cycles", "2", "--json"])
    assert code == 0
    r = json.loads(out)
    assert r["drag"]["cached"] is True
    for model in ("texture", "paper"):
        assert len(r[model]["advance_per_cycle_mm"]) == 2
        assert sum(r[model]["advance_per_cycle_mm"]) == pytest.approx(r[model]["net_advance_mm"])
    np.testing.assert_allclose(
        r["texture"]["advance_per_cycle_mm"], r["paper"]["advance_per_cycle_mm"], atol=1e-9
    )
    assert r["texture"]["work_mJ"] == pytest.approx(r["paper"]["work_mJ"], rel=1e-9)


def test_a_corrupt_cache_entry_is_run_again_and_replaced(tmp_path, monkeypatch, run_cli):
    path = _entry(tmp_path, monkeypatch)
    path.parent.mkdir(parents=True)
    path.write_text('{"version": 2, "summ')
    calls = []
    law = TextureLaw.sawtooth(2.0, FP, K, cells=4)

    def fake(sc, test, write=True, progress=None):
        calls.append(test)
        return DragRun(None, _summary(law), None)

    monkeypatch.setattr("bristlecrawler.jobs.drag.run_drag", fake)
    code, out, _ = run_cli(["predict", "--cycles", "1", "--json"])
    assert code == 0 and len(calls) == 1 and calls[0].direction == "cycle"
    assert json.loads(out)["drag"]["cached"] is False
    assert json.loads(path.read_text())["summary"]["texture"]["walls_mm"] == [0.0]
    assert [p.name for p in path.parent.iterdir()] == [path.name]  # no temporary left


@pytest.mark.parametrize(
    "args, word",
    [
        (["--cycles", "0"], "cycles"),
        (["nosuch"], "scenario"),
        (["--set", "substrate.pitch=-1"], "pitch"),
        (["--set", "bristle.count=1"], "count"),
    ],
)
def test_bad_input_one_line_exit_2_before_any_drag(args, word, tmp_path, monkeypatch, run_cli):
    _entry(tmp_path, monkeypatch)
    monkeypatch.setattr("bristlecrawler.jobs.drag.run_drag", _no_drag)
    code, out, err = run_cli(["predict", *args])
    assert code == 2 and out == ""
    assert len(err.strip().splitlines()) == 1 and word in err


def test_a_drag_test_past_the_step_bound_is_refused_before_it_starts(
    tmp_path, monkeypatch, run_cli
):
    """A wide pitch makes the prediction's drag test long (two pitches each way): refused
    as ``drag`` refuses it, one line with the estimate, exit 2, no drag test."""
    _entry(tmp_path, monkeypatch)
    monkeypatch.setattr("bristlecrawler.jobs.drag.run_drag", _no_drag)
    code, out, err = run_cli(["predict", "--set", "substrate.pitch=10000"])
    assert code == 2 and out == ""
    assert len(err.strip().splitlines()) == 1 and "time steps" in err


def _fake_drag(monkeypatch, calls):
    law = TextureLaw.sawtooth(2.0, FP, K, cells=4)

    def fake(sc, test, write=True, progress=None):
        calls.append(test)
        return DragRun(None, _summary(law), None)

    monkeypatch.setattr("bristlecrawler.jobs.drag.run_drag", fake)


@pytest.mark.parametrize(
    "content", ["[1, 2]", '"summary"', '{"version": 2, "summary": [1]}', "null", "3"]
)
def test_a_cache_entry_of_the_wrong_shape_is_one_warning_and_run_again(
    content, tmp_path, monkeypatch, run_cli
):
    path = _entry(tmp_path, monkeypatch)
    path.parent.mkdir(parents=True)
    path.write_text(content)
    calls = []
    _fake_drag(monkeypatch, calls)
    code, out, err = run_cli(["predict", "--cycles", "1", "--json"])
    assert code == 0 and len(calls) == 1
    assert json.loads(out)["drag"]["cached"] is False
    assert err.count("warning:") == 1 and "not a drag summary" in err
    assert json.loads(path.read_text())["version"] == predict.CACHE_VERSION  # replaced


def _constant_entry(path):
    path.parent.mkdir(parents=True, exist_ok=True)
    law = TextureLaw.constant(FP, FN, K, pitch=2.0)
    path.write_text(dumps_strict({"version": predict.CACHE_VERSION, "summary": _summary(law)}))


@pytest.mark.parametrize("how", ["group-writable folder", "group-writable entry", "other user"])
def test_a_cache_entry_others_could_write_is_not_used(how, tmp_path, monkeypatch, run_cli):
    """Its numbers would be the prediction: one warning, and the drag test runs."""
    path = _entry(tmp_path, monkeypatch)
    _constant_entry(path)
    if how == "group-writable folder":
        path.parent.chmod(0o775)
    elif how == "group-writable entry":
        path.chmod(0o664)
    else:
        uid = __import__("os").getuid()
        monkeypatch.setattr("os.getuid", lambda: uid + 1)
    calls = []
    _fake_drag(monkeypatch, calls)
    code, out, err = run_cli(["predict", "--cycles", "1", "--json"])
    assert code == 0 and len(calls) == 1
    assert json.loads(out)["drag"]["cached"] is False
    assert err.count("warning:") == 1


@pytest.mark.parametrize("what", ["fifo", "folder", "link"])
def test_a_cache_entry_that_is_not_a_regular_file_is_run_again(
    what, tmp_path, monkeypatch, run_cli
):
    import os
    import threading

    path = _entry(tmp_path, monkeypatch)
    path.parent.mkdir(parents=True)
    if what == "fifo":
        os.mkfifo(path)
    elif what == "folder":
        path.mkdir()
    else:
        _constant_entry(tmp_path / "elsewhere" / "entry.json")
        path.symlink_to(tmp_path / "elsewhere" / "entry.json")
    calls, fired = [], []

    def unblock():  # a reader stuck on the FIFO goes on: the test fails, not hangs
        fired.append(True)
        os.close(os.open(path, os.O_WRONLY | os.O_NONBLOCK))

    timer = threading.Timer(10.0, unblock)
    if what == "fifo":
        timer.start()
    _fake_drag(monkeypatch, calls)
    try:
        code, _, err = run_cli(["predict", "--cycles", "1", "--json"])
    finally:
        timer.cancel()
    assert code == 0 and len(calls) == 1 and not fired
    # A folder in the entry's place is not replaced either: a second warning says so.
    assert err.count("warning:") == (2 if what == "folder" else 1)


def test_the_drag_cache_is_private_whatever_the_umask(tmp_path, monkeypatch, run_cli):
    import os
    import stat

    path = _entry(tmp_path, monkeypatch)
    _fake_drag(monkeypatch, [])
    old = os.umask(0)
    try:
        code, _, _ = run_cli(["predict", "--cycles", "1", "--json"])
    finally:
        os.umask(old)
    assert code == 0
    assert stat.S_IMODE(path.parent.stat().st_mode) == 0o700
    assert stat.S_IMODE(path.stat().st_mode) == 0o600
