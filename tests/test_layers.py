"""The layers run one way: each package imports only the layers below it.

What the import scan sees: every ``import`` and ``from ... import`` statement of the
source, at module level and inside functions (a lazy import is a dependency all the same:
it runs the first time the function does, and a cycle through one breaks as soon as the
import order changes), under ``if TYPE_CHECKING`` too; relative imports are resolved
against the importing module's package, and ``from bristlecrawler import fe`` or ``from
bristlecrawler.crawler import model`` is an import of the module named. What it cannot
see: modules named by a string (``importlib.import_module``), as the package root's lazy
``bristlecrawler.crawler`` does.

The checks:

* every layer (subpackage or top-level module) has an entry in the allowed map, and
  imports only the layers its entry names;
* the allowed map and the layers' actual imports have no cycle;
* modules import each other without a cycle;
* no module imports another module's private name (leading underscore, not a dunder),
  nor a private module from outside the package that holds it (``bristlecrawler._x64``
  belongs to the whole package; ``bristlecrawler.fe._x`` only to ``fe``);
* a fresh interpreter importing a layer does not load the heavy or edge libraries the
  layer has no business with.
"""

import ast
import pathlib
import subprocess
import sys
from collections.abc import Iterator

import pytest

import bristlecrawler

ROOT = pathlib.Path(bristlecrawler.__file__).parent
PACKAGE = "bristlecrawler"
#: The package root's own layer (``bristlecrawler/__init__.py``: the reduced model and
#: ``__version__``).
TOP = "__init__"
#: The bottom layers every layer may import: the errors, the state codes, float64, file
#: handling, the typed results every model gives, and the declaration of settings (so a
#: model below the FE core, the reduced one, declares its settings as the FE core does).
BASE = {"errors", "states", "_x64", "_files", "results", "settings"}
EVERYTHING_BELOW_THE_CLI = (
    BASE
    | {"_pytree", "fe", "contact", "reduced", "actuators", TOP}
    | {"crawler", "experiment", "verification", "io", "scenario", "viz", "studies", "jobs"}
    | {"export"}
)

#: Layer -> the package's own layers it may import.
ALLOWED = {
    "errors": set(),
    "states": set(),
    "_x64": set(),
    "_files": set(),
    "results": {"errors"},
    "settings": {"errors"},
    "_pytree": {"_x64"},
    TOP: {"errors", "reduced"},
    "fe": BASE | {"_pytree"},
    "reduced": BASE,
    "contact": BASE | {"_pytree", "fe"},
    "actuators": BASE | {"reduced"},
    "crawler": BASE | {"_pytree", "fe", "contact", "reduced", "actuators"},
    "experiment": BASE | {"reduced", "actuators", "io"},
    "verification": BASE | {"fe", "contact", "reduced"},
    # Decks for other FE codes are written from the crawler's specs.
    "export": BASE | {"crawler", "contact"},
    # Run metadata records the package version.
    "io": BASE | {"reduced", TOP},
    # The edge validates the input of every model: the experiment commands' options are
    # generated from the experiment layer's declarations, as a scenario's from the crawler's.
    "scenario": BASE | {"fe", "contact", "reduced", "actuators", "crawler", "experiment", "io"},
    "viz": BASE | {"reduced", "crawler", "experiment", "io"},
    # Design studies sweep the models the scenarios describe; they run below the jobs.
    "studies": BASE | {"fe", "reduced", "crawler", "scenario", "io", "viz", TOP},
    # Jobs run everything below the CLI; `reproduce` runs design studies too.
    "jobs": BASE
    | {"fe", "contact", "reduced", "actuators", "crawler", "experiment", "io", "scenario"}
    | {"viz", "studies", "export"},
    "cli": EVERYTHING_BELOW_THE_CLI,
}

#: Module imports that close a cycle and stay for now, each with its reason. (A lazy
#: import from ``a`` to ``b``, both without the ``bristlecrawler.`` prefix.)
CYCLE_EXCEPTIONS: dict[tuple[str, str], str] = {}

#: Imports of a private name from another module that stay, each with its reason:
#: (importing module, imported module, name), without the ``bristlecrawler.`` prefix.
PRIVATE_EXCEPTIONS: dict[tuple[str, str, str], str] = {}

#: Layer -> third-party modules that importing it must not load.
NOT_LOADED = {
    "bristlecrawler.settings": ("jax", "pydantic", "matplotlib", "xarray"),
    "bristlecrawler.results": ("jax", "pydantic", "matplotlib", "xarray"),
    "bristlecrawler.fe": ("pydantic", "matplotlib", "xarray", "rich", "typer"),
    "bristlecrawler.contact": ("pydantic", "matplotlib", "xarray", "rich", "typer"),
    "bristlecrawler.reduced": ("jax", "pydantic", "matplotlib", "xarray"),
    "bristlecrawler.crawler": ("pydantic", "matplotlib", "xarray", "rich", "typer"),
    "bristlecrawler.actuators": ("jax", "pydantic", "matplotlib"),
    # The report's parts import their models when they run: listing them is free.
    "bristlecrawler.jobs.reproduce": ("jax", "matplotlib", "xarray", "distributed", "rich"),
}


# ----------------------------------------------------------------------------- the scan


def _modules(root: pathlib.Path) -> dict[str, pathlib.Path]:
    """Dotted module name -> file, for the package at ``root``."""
    out = {}
    for path in sorted(root.rglob("*.py")):
        parts = [root.name, *path.relative_to(root).with_suffix("").parts]
        if parts[-1] == "__init__":
            parts.pop()
        out[".".join(parts)] = path
    return out


def _package_of(name: str, path: pathlib.Path) -> str:
    """The package a relative import in module ``name`` starts from."""
    return name if path.name == "__init__.py" else name.rpartition(".")[0]


def _scan_node(node, name: str, path: pathlib.Path, modules) -> Iterator[tuple]:
    """(alias, imported module, imported name or None) for each of the package's modules
    or names one import statement of module ``name`` brings in; ``from a import b`` where
    ``a.b`` is a module imports that module."""
    if isinstance(node, ast.Import):
        for alias in node.names:
            if alias.name.split(".")[0] == PACKAGE:
                yield alias, alias.name, None
    elif isinstance(node, ast.ImportFrom):
        if node.level:
            base = _package_of(name, path).split(".")
            base = base[: len(base) - node.level + 1]
            source = ".".join(base + ([node.module] if node.module else []))
        else:
            source = node.module or ""
        if source.split(".")[0] == PACKAGE:
            for alias in node.names:
                full = f"{source}.{alias.name}"
                yield (alias, full, None) if full in modules else (alias, source, alias.name)


def _scan(name: str, path: pathlib.Path, modules) -> Iterator[tuple[str, str | None, int]]:
    """(imported module, imported name or None, line) for each of the package's imports in
    module ``name``."""
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import | ast.ImportFrom):
            for _, target, imported in _scan_node(node, name, path, modules):
                yield target, imported, node.lineno


def _short(module: str) -> str:
    return module.partition(".")[2] or TOP


def _layer(short: str) -> str:
    """The layer of a module named without the ``bristlecrawler.`` prefix."""
    return short.split(".")[0]


def _graph(root: pathlib.Path) -> dict[str, set[str]]:
    """Module -> the package's modules it imports (short names)."""
    modules = _modules(root)
    return {
        _short(m): {_short(t) for t, _, _ in _scan(m, p, modules) if t != m}
        for m, p in modules.items()
    }


def _imports(path: pathlib.Path, root: pathlib.Path = ROOT) -> set[str]:
    """The layers one file imports."""
    modules = _modules(root)
    name = next((m for m, p in modules.items() if p == path), f"{PACKAGE}._scanned")
    return {_layer(_short(t)) for t, _, _ in _scan(name, path, modules)}


def _cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The strongly connected components of more than one node, or with a self-loop
    (Tarjan's algorithm)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    found = []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in sorted(graph.get(v, ())):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            part = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                part.append(w)
                if w == v:
                    break
            if len(part) > 1 or v in graph.get(v, ()):
                found.append(sorted(part))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return found


def _module_cycles(root: pathlib.Path, exceptions=CYCLE_EXCEPTIONS) -> list[list[str]]:
    graph = _graph(root)
    for a, b in exceptions:
        graph.get(a, set()).discard(b)
    return _cycles(graph)


def _layer_graph(root: pathlib.Path) -> dict[str, set[str]]:
    out: dict[str, set[str]] = {}
    for module, targets in _graph(root).items():
        out.setdefault(_layer(module), set()).update(
            _layer(t) for t in targets if _layer(t) != _layer(module)
        )
    return out


def _private(part: str) -> bool:
    return part.startswith("_") and not (part.startswith("__") and part.endswith("__"))


def _private_imports(root: pathlib.Path, exceptions=PRIVATE_EXCEPTIONS) -> list[str]:
    """Each import of another module's private name, or of a private module from
    outside its package, as ``file:line: what``."""
    modules = _modules(root)
    wrong = []
    for name, path in modules.items():
        for target, attr, line in _scan(name, path, modules):
            where = f"{path.relative_to(root)}:{line}"
            parts = target.split(".")
            for i, part in enumerate(parts):
                owner = ".".join(parts[:i])
                if _private(part) and not (name == owner or name.startswith(owner + ".")):
                    wrong.append(f"{where}: private module {target}")
                    break
            key = (_short(name), _short(target), attr)
            if attr and _private(attr) and target != name and key not in exceptions:
                wrong.append(f"{where}: private name {attr} of {target}")
    return wrong


def _private_attributes(root: pathlib.Path) -> list[str]:
    """Each ``alias._name`` where ``alias`` is one of the package's modules imported by
    name (``from bristlecrawler import fe``, then ``fe._pytree``), as ``file:line: what``."""
    modules = _modules(root)
    wrong = []
    for name, path in modules.items():
        tree = ast.parse(path.read_text(encoding="utf-8"))
        aliases = {}
        for node in ast.walk(tree):
            if isinstance(node, ast.Import | ast.ImportFrom):
                for alias, target, imported in _scan_node(node, name, path, modules):
                    if imported is None and (alias.asname or "." not in alias.name):
                        aliases[alias.asname or alias.name] = target
        for node in ast.walk(tree):
            if (
                isinstance(node, ast.Attribute)
                and isinstance(node.value, ast.Name)
                and node.value.id in aliases
                and _private(node.attr)
                and aliases[node.value.id] != name
            ):
                where = f"{path.relative_to(root)}:{node.lineno}"
                wrong.append(f"{where}: private name {node.attr} of {aliases[node.value.id]}")
    return wrong


def _layers(root: pathlib.Path) -> set[str]:
    """The package's layers: its subpackages, top-level modules and root."""
    return {_layer(_short(m)) for m in _modules(root)}


# ------------------------------------------------------------------------- the checks


def test_every_layer_has_an_entry_in_the_allowed_map():
    assert _layers(ROOT) - set(ALLOWED) == set(), "layers missing from ALLOWED"
    assert set(ALLOWED) - _layers(ROOT) == set(), "ALLOWED names layers that do not exist"


@pytest.mark.parametrize("layer", sorted(ALLOWED))
def test_a_layer_imports_only_the_layers_below_it(layer):
    wrong = {}
    for name, targets in _graph(ROOT).items():
        bad = {_layer(t) for t in targets} - ALLOWED[layer] - {layer}
        if _layer(name) == layer and bad:
            wrong[name] = sorted(bad)
    assert not wrong, f"{layer} imports layers above it: {wrong}"


def test_the_allowed_map_has_no_cycle():
    assert _cycles(ALLOWED) == []


def test_the_layers_import_each_other_without_a_cycle():
    assert _cycles(_layer_graph(ROOT)) == []


def test_the_modules_import_each_other_without_a_cycle():
    assert _module_cycles(ROOT) == []


def test_each_cycle_exception_is_still_needed():
    graph = _graph(ROOT)
    stale = [edge for edge in CYCLE_EXCEPTIONS if edge[1] not in graph.get(edge[0], ())]
    assert stale == [], "exceptions whose import is gone"


def test_no_module_imports_a_private_name_of_another():
    assert _private_imports(ROOT) == []


def test_no_module_reads_a_private_name_of_another():
    assert _private_attributes(ROOT) == []


@pytest.mark.parametrize("layer", sorted(NOT_LOADED))
def test_importing_a_layer_does_not_load_the_edge_libraries(layer):
    names = NOT_LOADED[layer]
    code = f"import sys, {layer}\nprint(','.join(m for m in {names!r} if m in sys.modules))"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "", f"importing {layer} loaded {out.stdout.strip()}"


# ------------------------------------------------------- the checks see planted faults


def _plant(tmp_path: pathlib.Path, files: dict[str, str]) -> pathlib.Path:
    """A package named like ours under ``tmp_path`` with the given files."""
    root = tmp_path / PACKAGE
    for rel, text in files.items():
        path = root / rel
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text, encoding="utf-8")
    for folder in {p.parent for p in root.rglob("*.py")} | {root}:
        (folder / "__init__.py").touch()
    return root


def test_the_check_sees_a_lazy_import(tmp_path):
    """The import scan reads imports inside functions too (the cycle it guards against was
    a lazy one)."""
    f = tmp_path / "m.py"
    f.write_text("def f():\n    from bristlecrawler.viz.progress import sim_progress\n")
    assert _imports(f) == {"viz"}


def test_the_check_sees_relative_and_package_imports(tmp_path):
    root = _plant(
        tmp_path,
        {
            "fe/model.py": "",
            "crawler/model.py": "",
            "crawler/a.py": "from . import model\nfrom ..fe import model as m\n",
            "crawler/b.py": "from bristlecrawler import fe\n",
            "crawler/c.py": "from bristlecrawler.crawler import model\n",
            "crawler/d.py": "from .model import X\n",
        },
    )
    graph = _graph(root)
    assert graph["crawler.a"] == {"crawler.model", "fe.model"}
    assert graph["crawler.b"] == {"fe"}
    assert graph["crawler.c"] == {"crawler.model"}
    assert graph["crawler.d"] == {"crawler.model"}
    assert _imports(root / "crawler" / "a.py", root) == {"crawler", "fe"}


def test_the_check_sees_a_missing_layer(tmp_path):
    root = _plant(tmp_path, {"fe/model.py": "", "newlayer/x.py": "", "tool.py": ""})
    assert _layers(root) == {TOP, "fe", "newlayer", "tool"}
    assert {"newlayer", "tool"} - set(ALLOWED)


def test_the_check_sees_a_layer_cycle(tmp_path):
    root = _plant(
        tmp_path,
        {
            "studies/run.py": "def f():\n    from bristlecrawler.jobs.estimates import announce\n",
            "jobs/estimates.py": "",
            "jobs/study.py": "from bristlecrawler.studies import run\n",
        },
    )
    assert _cycles(_layer_graph(root)) == [["jobs", "studies"]]
    assert _cycles({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == [["a", "b", "c"]]
    assert _cycles({"a": {"a"}}) == [["a"]]


def test_the_check_sees_a_module_cycle(tmp_path):
    files = {
        "crawler/drag.py": "def run():\n    from .drag_analysis import result_of\n",
        "crawler/drag_analysis.py": "from bristlecrawler.crawler.drag import pitch\n",
    }
    root = _plant(tmp_path, files)
    assert _module_cycles(root, {}) == [["crawler.drag", "crawler.drag_analysis"]]
    assert _module_cycles(root, {("crawler.drag", "crawler.drag_analysis"): "why"}) == []


def test_the_check_sees_a_private_import(tmp_path):
    root = _plant(
        tmp_path,
        {
            "_base.py": "",
            "fe/_helper.py": "",
            "fe/model.py": "from bristlecrawler.fe._helper import x\nfrom .._base import y\n",
            "crawler/model.py": "def _add_contact():\n    pass\n",
            "crawler/drag.py": "from .model import _add_contact, __doc__\n",
            "crawler/actuation.py": "from bristlecrawler.fe._helper import pytree\n",
            "crawler/job.py": "from bristlecrawler.fe import _helper\n",
        },
    )
    assert sorted(_private_imports(root, {})) == [
        "crawler/actuation.py:1: private module bristlecrawler.fe._helper",
        "crawler/drag.py:1: private name _add_contact of bristlecrawler.crawler.model",
        "crawler/job.py:1: private module bristlecrawler.fe._helper",
    ]
    allowed = {("crawler.drag", "crawler.model", "_add_contact"): "why"}
    assert len(_private_imports(root, allowed)) == 2


def test_the_check_sees_a_private_attribute(tmp_path):
    root = _plant(
        tmp_path,
        {
            "fe/_pytree.py": "",
            "fe/modal.py": "",
            "crawler/actuation.py": "from bristlecrawler import fe\nfe._pytree.pytree()\n",
            "crawler/drag.py": "from ..fe import modal as m\nm._mass_fn\nm.__name__\n",
        },
    )
    assert sorted(_private_attributes(root)) == [
        "crawler/actuation.py:2: private name _pytree of bristlecrawler.fe",
        "crawler/drag.py:2: private name _mass_fn of bristlecrawler.fe.modal",
    ]
