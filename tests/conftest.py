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


#: A test process holding more than this (MB resident, ``BRISTLECRAWLER_TEST_KEEP_MB``) drops
#: its compiled programs after a module; below it, they stay loaded for the next modules.
KEEP_PROGRAMS_MB = float(os.environ.get("BRISTLECRAWLER_TEST_KEEP_MB", "3000"))
_memory = {"modules": 0, "cleared": 0, "peak_mb": 0.0}


def _resident_mb() -> float:
    """This process's resident memory (MB); infinite where /proc cannot tell (then the
    programs are always dropped)."""
    try:
        with open("/proc/self/status") as f:
            line = next(x for x in f if x.startswith("VmRSS:"))
        return float(line.split()[1]) / 1024.0
    except (OSError, StopIteration, ValueError, IndexError):
        return float("inf")


@pytest.fixture(autouse=True, scope="module")
def _free_compiled_programs():
    """Drop JAX's compiled programs after a test module once the process holds more than
    :data:`KEEP_PROGRAMS_MB`. The full suite compiles hundreds of programs (the FE
    crawler's step is 8 MB of machine code); kept for the whole process they grew its
    memory until XLA aborted in a later compile (twice, in tests/fe). Below the bound the
    programs stay loaded, so that the next modules that use the same kernels or the same
    shared structure (tests/structures.py) neither compile nor load them again. The stored
    programs stay on disk either way."""
    yield
    mb = _resident_mb()
    _memory["modules"] += 1
    _memory["peak_mb"] = max(_memory["peak_mb"], mb if mb != float("inf") else 0.0)
    if mb <= KEEP_PROGRAMS_MB:
        return
    import jax

    from bristlecrawler.fe.programs import clear_loaded

    jax.clear_caches()
    clear_loaded()
    _memory["cleared"] += 1


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
    if _memory["modules"]:
        terminalreporter.write_line(
            f"compiled programs: dropped after {_memory['cleared']} of {_memory['modules']} "
            f"modules (bound {KEEP_PROGRAMS_MB:.0f} MB resident); largest resident memory "
            f"after a module {_memory['peak_mb']:.0f} MB"
        )
    slow = sorted(((t, n) for n, t in _unmarked_slow.items() if t > SLOW_TEST_S), reverse=True)
    if slow:
        terminalreporter.section("unmarked tests over 10 s (mark them slow)")
        for t, n in slow:
            terminalreporter.write_line(f"{t:7.1f} s  {n}")
