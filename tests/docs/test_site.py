"""The documentation site builds with `mkdocs build --strict` (a broken link, a missing
page or an API reference to a name that does not exist fails), and its generated
reference pages hold what the code defines."""

import importlib.util
import os
import subprocess
import sys

import pytest

from .pages import ROOT


def _require_mkdocs():
    if importlib.util.find_spec("mkdocs") is None:
        if os.environ.get("BRISTLECRAWLER_REQUIRE_DOCS", "") not in ("", "0"):
            pytest.fail("mkdocs is not installed (pip install -e '.[docs]')")
        pytest.skip("the docs extra is not installed (pip install -e '.[docs]')")


@pytest.fixture(scope="module")
def site(tmp_path_factory):
    _require_mkdocs()
    out = tmp_path_factory.mktemp("site")
    env = os.environ | {"NO_MKDOCS_2_WARNING": "1", "PYTHONPATH": str(ROOT / "src")}
    proc = subprocess.run(
        [sys.executable, "-m", "mkdocs", "build", "--strict", "--site-dir", str(out)],
        cwd=ROOT,
        env=env,
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert proc.returncode == 0, proc.stderr[-3000:]
    return out


def test_strict_build_has_every_page(site):
    for page in ("index.html", "findings/index.html", "reference/api/index.html"):
        assert (site / page).is_file(), page


def test_scenario_reference_is_generated_from_the_schema(site):
    from bristlecrawler.scenario.keys import scenario_keys

    html = (site / "reference" / "scenario" / "index.html").read_text()
    assert "<!-- scenario-keys -->" not in html  # the marker was replaced
    for key in scenario_keys():
        assert f"<code>{key.key.split('.')[-1]}</code>" in html, key.key


def test_output_reference_lists_every_declared_crawler_variable(site):
    from bristlecrawler.crawler.quantities import MARKER, QUANTITIES

    html = (site / "reference" / "outputs" / "index.html").read_text()
    assert MARKER not in html
    for q in QUANTITIES:
        assert f"<td><code>{q.name}</code></td>" in html, q.name


def test_api_reference_documents_the_reduced_model(site):
    html = (site / "reference" / "api" / "index.html").read_text()
    for name in ("ReducedCrawler", "simulate", "calibrate", "analyze", "load_scenario"):
        assert name in html, name


def test_outputs_reference_lists_every_variable_of_reduced_nc(site):
    """The file's variables are its declarations, and the built reference page lists
    each of them (generated from the same declarations) and its coordinates."""
    import bristlecrawler as bc
    from bristlecrawler.io.netcdf import REDUCED_VARIABLES, reduced_dataset

    res = bc.simulate(bc.ReducedCrawler.two_bristle(), bc.Sin2Stroke(20.0, 20.0), cycles=1)
    ds = reduced_dataset(res)
    declared = {v.name: v for v in REDUCED_VARIABLES}
    for name, var in ds.data_vars.items():
        assert name in declared, name
        assert var.attrs.get("units", "") == declared[name].unit, name
    html = (site / "reference" / "outputs" / "index.html").read_text()
    assert "reduced-variables" not in html
    for v in REDUCED_VARIABLES:
        assert f"<td><code>{v.name}</code></td>" in html, v.name
    text = (ROOT / "docs" / "reference" / "outputs.md").read_text()
    for name in ds.coords:
        assert f"`{name}`" in text, name


def test_outputs_reference_lists_every_declared_variable_of_drag_nc(site):
    from bristlecrawler.crawler.drag_analysis import DRAG_VARIABLES

    html = (site / "reference" / "outputs" / "index.html").read_text()
    assert "drag-variables" not in html
    for v in DRAG_VARIABLES:
        assert f"<td><code>{v.name}</code></td>" in html, v.name


def test_cli_reference_lists_every_declared_option_of_the_generated_tables(site):
    from bristlecrawler.scenario.keys import COMMAND_TABLES, command_table
    from bristlecrawler.scenario.strict import option_names

    html = (site / "reference" / "cli" / "index.html").read_text()
    assert "<!-- options:" not in html
    for command in COMMAND_TABLES:
        for flag in option_names(command_table(command)).values():
            assert f"<td><code>{flag}</code></td>" in html, (command, flag)
