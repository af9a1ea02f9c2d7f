"""The layers run one way: each package imports only the layers below it.

Two checks: every import statement in the source (module level and inside functions)
against the allowed map, and a fresh interpreter importing a layer, which must not load
the heavy or edge libraries the layer has no business with.
"""

import ast
import pathlib
import subprocess
import sys

import pytest

import bristlecrawler

ROOT = pathlib.Path(bristlecrawler.__file__).parent
BASE = {"errors", "states", "_x64"}

#: Package -> the package's own layers it may import.
ALLOWED = {
    "fe": BASE,
    "reduced": BASE,
    "contact": BASE | {"fe"},
    "actuators": BASE | {"reduced"},
    "crawler": BASE | {"fe", "contact", "reduced", "actuators"},
    "experiment": BASE | {"reduced", "actuators", "io"},
    "verification": BASE | {"fe", "contact", "reduced"},
    "io": BASE | {"reduced"},
    "scenario": BASE | {"fe", "contact", "reduced", "actuators", "crawler", "io"},
    "viz": BASE | {"reduced", "crawler", "experiment", "io"},
    # Jobs run everything below the CLI; `reproduce` runs design studies too.
    "jobs": BASE
    | {"fe", "contact", "reduced", "actuators", "crawler", "experiment", "io", "scenario"}
    | {"viz", "studies"},
}

#: Layer -> third-party modules that importing it must not load.
NOT_LOADED = {
    "bristlecrawler.fe": ("pydantic", "matplotlib", "xarray", "rich", "typer"),
    "bristlecrawler.contact": ("pydantic", "matplotlib", "xarray", "rich", "typer"),
    "bristlecrawler.reduced": ("jax", "pydantic", "matplotlib", "xarray"),
    "bristlecrawler.crawler": ("pydantic", "matplotlib", "xarray", "rich", "typer"),
    "bristlecrawler.actuators": ("jax", "pydantic", "matplotlib"),
    # The report's parts import their models when they run: listing them is free.
    "bristlecrawler.jobs.reproduce": ("jax", "matplotlib", "xarray", "distributed", "rich"),
}


def _imports(path: pathlib.Path) -> set[str]:
    found = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            found.update(a.name for a in node.names)
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            found.add(node.module)
    return {n.split(".")[1] for n in found if n.startswith("bristlecrawler.")}


@pytest.mark.parametrize("layer", sorted(ALLOWED))
def test_a_layer_imports_only_the_layers_below_it(layer):
    wrong = {}
    for path in sorted((ROOT / layer).rglob("*.py")):
        bad = _imports(path) - ALLOWED[layer] - {layer}
        if bad:
            wrong[str(path.relative_to(ROOT))] = sorted(bad)
    assert not wrong, f"{layer} imports layers above it: {wrong}"


@pytest.mark.parametrize("layer", sorted(NOT_LOADED))
def test_importing_a_layer_does_not_load_the_edge_libraries(layer):
    names = NOT_LOADED[layer]
    code = f"import sys, {layer}\nprint(','.join(m for m in {names!r} if m in sys.modules))"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "", f"importing {layer} loaded {out.stdout.strip()}"


def test_the_check_sees_a_lazy_import(tmp_path):
    """The import scan reads imports inside functions too (the cycle it guards against was
    a lazy one)."""
    f = tmp_path / "m.py"
    f.write_text("def f():\n    from bristlecrawler.viz.progress import sim_progress\n")
    assert _imports(f) == {"viz"}
