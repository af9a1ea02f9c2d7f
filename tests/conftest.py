"""Shared test settings (hypothesis profiles sized for a 2-core CI machine) and fixtures."""

import os

import pytest
from hypothesis import HealthCheck, settings

from bristlecrawler.cli.app import main

# The CLI commands enable JAX's persistent compilation cache, for the rest of the pytest
# process too. Keep the suite off the user's cache: a run of the suite once crashed
# (segmentation fault) deserialising an entry of it while other processes were writing
# to it, and a fresh CI machine gains nothing from it. BRISTLECRAWLER_NO_JAX_CACHE=0 opts in.
os.environ.setdefault("BRISTLECRAWLER_NO_JAX_CACHE", "1")

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
    they grew its memory until XLA aborted in a later compile (twice, in tests/fe)."""
    yield
    import jax

    jax.clear_caches()
