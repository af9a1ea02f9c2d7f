"""Shared test settings (hypothesis profiles sized for a 2-core CI machine) and fixtures."""

import atexit
import os
import shutil
import tempfile

import pytest
from hypothesis import HealthCheck, settings

from bristlecrawler.cli.app import main

# The FE programs are stored in a cache folder of this test process's own (each xdist
# worker has one; the subprocesses and Dask workers a test starts share it: the stored
# programs are written atomically), so that a module that builds a structure an earlier
# one built loads its programs instead of tracing and compiling them again. JAX's own
# persistent cache stays off: its entries are written in place, and a run of the suite
# once crashed reading one that another process was writing. Setting
# BRISTLECRAWLER_JAX_CACHE (or BRISTLECRAWLER_NO_JAX_CACHE=1) overrides.
if "BRISTLECRAWLER_JAX_CACHE" not in os.environ:
    _cache = tempfile.mkdtemp(prefix="bristlecrawler-test-cache-")
    os.environ["BRISTLECRAWLER_JAX_CACHE"] = _cache
    atexit.register(shutil.rmtree, _cache, ignore_errors=True)
os.environ.setdefault("BRISTLECRAWLER_XLA_CACHE", "0")

settings.register_profile(
    "ci", max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow]
)
settings.register_profile("thorough", max_examples=500, deadline=None)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "ci"))


def pytest_xdist_auto_num_workers(config):
    """For ``pytest -n auto --dist loadfile``: one test process per core, at most four
    (each holds the FE programs it compiled, a few GB at its peak)."""
    return max(1, min(os.cpu_count() or 1, 4))


@pytest.fixture(autouse=True)
def _costs_file(tmp_path_factory, monkeypatch):
    """Commands keep the costs they measure for later estimates: not in the user's file."""
    folder = tmp_path_factory.mktemp("costs")
    monkeypatch.setenv("BRISTLECRAWLER_COSTS", str(folder / "costs.json"))


@pytest.fixture
def run_cli(capsys):
    """Run the CLI in-process; returns (exit code, stdout, stderr)."""

    def run(args):
        try:
            main(args)
            code = 0
        except SystemExit as exc:
            code = exc.code
        out = capsys.readouterr()
        return code, out.out, out.err

    return run


@pytest.fixture(autouse=True, scope="module")
def _free_compiled_programs():
    """Drop JAX's compiled programs after each test module. The suite compiles hundreds of
    programs (the FE crawler's step is 8 MB of machine code); kept for the whole process
    they grew its memory until XLA aborted in a later compile (twice, in tests/fe). The
    stored programs stay on disk for the next module."""
    yield
    import jax

    from bristlecrawler.fe.programs import clear_loaded

    jax.clear_caches()
    clear_loaded()


#: A test that takes longer than this (s, setup and teardown included) belongs in the slow
#: lane: mark it ``@pytest.mark.slow``. The suite lists the unmarked ones at its end; a
#: report, never a failure (a shared CI machine must not fail a build on a timing).
SLOW_TEST_S = 10.0
_unmarked_slow: dict[str, float] = {}


def pytest_runtest_logreport(report):
    if "slow" in report.keywords:
        return
    _unmarked_slow[report.nodeid] = _unmarked_slow.get(report.nodeid, 0.0) + report.duration


def pytest_terminal_summary(terminalreporter):
    slow = sorted(((t, n) for n, t in _unmarked_slow.items() if t > SLOW_TEST_S), reverse=True)
    if slow:
        terminalreporter.section("unmarked tests over 10 s (mark them slow)")
        for t, n in slow:
            terminalreporter.write_line(f"{t:7.1f} s  {n}")
