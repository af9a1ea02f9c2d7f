"""Shared test settings (hypothesis profiles sized for a 2-core CI machine) and fixtures."""

import atexit
import os
import shutil
import subprocess
import sys
import tempfile

#: XLA's CPU fusion emitters off and LLVM's optimisation at level 0: the suite is mostly
#: compilation of programs that then run a few steps. Level 0 halves a program's compile
#: time and makes its steps 2-3 times slower; the fusion emitters off take a quarter to a
#: third off the small programs' compile times (docs/performance.md#compilation). The whole
#: suite on both cores: 843 s with XLA's defaults for LLVM, 615 s at level 0. Results
#: move by round-off only. Used where this jaxlib knows the flags and XLA_FLAGS is not
#: already set; XLA aborts on a flag it does not know.
TEST_XLA_FLAGS = "--xla_cpu_use_fusion_emitters=false --xla_backend_optimization_level=0"


def _xla_accepts(flags: str) -> bool:
    probe = "import jax.numpy as jnp; jnp.zeros(1).block_until_ready()"
    env = {**os.environ, "XLA_FLAGS": flags, "JAX_PLATFORMS": "cpu"}
    try:
        cmd = [sys.executable, "-c", probe]
        done = subprocess.run(cmd, env=env, capture_output=True, timeout=120)
    except (OSError, subprocess.TimeoutExpired):
        return False
    return done.returncode == 0


# Set before JAX starts its backend; xdist workers and subprocesses inherit it.
if "XLA_FLAGS" not in os.environ and _xla_accepts(TEST_XLA_FLAGS):
    os.environ["XLA_FLAGS"] = TEST_XLA_FLAGS

import pytest  # noqa: E402
from hypothesis import HealthCheck, settings  # noqa: E402

from bristlecrawler.cli.app import main  # noqa: E402

# The FE programs are stored in a cache folder of this run's own (set before the xdist
# workers start, so they, the subprocesses and the Dask workers the tests start share it:
# the stored programs are written atomically under a lock), so that a module that builds a
# structure an earlier one built loads its programs instead of tracing and compiling them
# again. JAX's own persistent cache stays off: its entries are written in place, and a run
# of the suite once crashed reading one that another process was writing. Setting
# BRISTLECRAWLER_JAX_CACHE (or BRISTLECRAWLER_NO_JAX_CACHE=1) overrides.
if "BRISTLECRAWLER_JAX_CACHE" not in os.environ:
    _cache = tempfile.mkdtemp(prefix="bristlecrawler-test-cache-")
    os.environ["BRISTLECRAWLER_JAX_CACHE"] = _cache
    atexit.register(shutil.rmtree, _cache, ignore_errors=True)
    # Its entries are signed with a key of the run's own too, not the user's in ~/.config
    # (a folder the user keeps between runs keeps the user's key).
    os.environ.setdefault("BRISTLECRAWLER_CACHE_KEY", os.path.join(_cache, "cache-key"))
os.environ.setdefault("BRISTLECRAWLER_XLA_CACHE", "0")
# Every load and compile of a stored program, by every test process and the subprocesses
# they start, in a file of this run's own, for the report at its end (which structures cost
# what).
if "BRISTLECRAWLER_PROGRAM_LOG" not in os.environ:
    _log = tempfile.mkdtemp(prefix="bristlecrawler-test-log-")
    os.environ["BRISTLECRAWLER_PROGRAM_LOG"] = os.path.join(_log, "programs.jsonl")
    atexit.register(shutil.rmtree, _log, ignore_errors=True)

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


#: Seconds JAX spent tracing, lowering and compiling (XLA) in this process so far, from its
#: monitoring events; each test's share travels with its reports to the controller.
_JAX_EVENTS = frozenset(
    {
        "/jax/core/compile/jaxpr_trace_duration",
        "/jax/core/compile/jaxpr_to_mlir_module_duration",
        "/jax/core/compile/backend_compile_duration",
    }
)
_compiling = {"spent": 0.0, "reported": 0.0}
_compile_by_file: dict[str, list[float]] = {}


def _on_jax_event(event, duration, **kwargs):
    if event in _JAX_EVENTS:
        _compiling["spent"] += duration


def pytest_configure(config):
    import jax.monitoring

    jax.monitoring.register_event_duration_secs_listener(_on_jax_event)


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_makereport(item, call):
    outcome = yield
    spent = _compiling["spent"]
    outcome.get_result().user_properties.append(("jax_compile_s", spent - _compiling["reported"]))
    _compiling["reported"] = spent


def pytest_runtest_logreport(report):
    compiling = dict(report.user_properties).get("jax_compile_s", 0.0)
    totals = _compile_by_file.setdefault(report.nodeid.split("::")[0], [0.0, 0.0])
    totals[0] += report.duration
    totals[1] += compiling
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
    _program_report(terminalreporter)
    _compile_report(terminalreporter)
    slow = sorted(((t, n) for n, t in _unmarked_slow.items() if t > SLOW_TEST_S), reverse=True)
    if slow:
        terminalreporter.section("unmarked tests over 10 s (mark them slow)")
        for t, n in slow:
            terminalreporter.write_line(f"{t:7.1f} s  {n}")


def _program_report(terminalreporter) -> None:
    """The stored programs the run compiled and loaded (from the program log), the
    costliest first: each distinct structure a test builds compiles its own."""
    import json
    from collections import defaultdict

    try:
        with open(os.environ["BRISTLECRAWLER_PROGRAM_LOG"]) as f:
            lines = [json.loads(x) for x in f if x.strip()]
    except (OSError, KeyError, ValueError):
        return
    total = defaultdict(lambda: [0, 0.0])
    for x in lines:
        total[x["program"], x["event"]][0] += 1
        total[x["program"], x["event"]][1] += x["seconds"]
    terminalreporter.section("stored FE programs: compiled and loaded")
    for (program, event), (n, s) in sorted(total.items(), key=lambda kv: -kv[1][1]):
        terminalreporter.write_line(f"{s:8.1f} s  {n:4d} x {event:8s} {program}")
    # One step program per structure: the tests that compiled one are where sharing a
    # structure would save the most.
    stepping = ("make_step", "make_driver")
    steps = [x for x in lines if x["event"] == "compile" and x["program"].endswith(stepping)]
    if steps:
        terminalreporter.section("stored step programs compiled, by test")
        for x in sorted(steps, key=lambda x: x.get("test", "")):
            where = x.get("test", f"pid {x['pid']}")
            terminalreporter.write_line(f"{x['seconds']:8.1f} s  {x['entry']}  {where}")


def _compile_report(terminalreporter, rows: int = 15) -> None:
    """How much of the test time was JAX tracing, lowering and compiling, over the whole
    run and for the modules that spent the most (compiles in threads can add up to more
    than a test's wall time; subprocesses are not counted)."""
    if not _compile_by_file:
        return
    wall = sum(t for t, _ in _compile_by_file.values())
    spent = sum(c for _, c in _compile_by_file.values())
    terminalreporter.section("JAX tracing and compiling, by module")
    terminalreporter.write_line(
        f"{spent:8.1f} s compiling (summed over threads) in tests that took {wall:.1f} s"
    )
    worst = sorted(_compile_by_file.items(), key=lambda kv: -kv[1][1])[:rows]
    for path, (t, c) in worst:
        terminalreporter.write_line(f"{c:8.1f} s of {t:7.1f} s  {path}")
