"""One direction of imports: each module of flexkane imports only from its own layer or earlier ones.

The layers follow the pipeline (docs/design.md, "The package as layers"); a module is in the layer of
the longest prefix of its name listed below. The check reads every module's source with :mod:`ast`
(imports at any depth, inside functions too), so nothing is imported and no side effect runs. A new
module must be given a layer here.
"""

from __future__ import annotations

import ast
import functools
import pathlib

import pytest

SRC = pathlib.Path(__file__).resolve().parents[1] / "src"
PACKAGE = "flexkane"

#: The layers, earliest first: (name, modules or packages in it).
LAYERS = [
    ("foundation", ["flexkane.errors", "flexkane._version", "flexkane.interruption", "flexkane.natural_order",
                    "flexkane.atomic", "flexkane.checked_cache", "flexkane.progress", "flexkane.extras",
                    "flexkane.forking", "flexkane.garbage_collection", "flexkane.limits"]),
    # the expression language of model files: parsing and evaluating user text, without a model
    ("expression language", ["flexkane.expression_syntax", "flexkane.expressions", "flexkane.expression_values"]),
    # shape functions of beams: mathematics that knows no model (the model's validation asks them)
    ("modes", ["flexkane.modes"]),
    # parts, model files, field values (numbers), validation, built-in models
    ("model", ["flexkane.model", "flexkane.builtin"]),
    ("kane", ["flexkane.kane"]),
    ("numerics", ["flexkane.numerics"]),
    ("simulate / linearize", ["flexkane.simulation", "flexkane.results", "flexkane.validity",
                              "flexkane.derivation_cache", "flexkane.run_manifest", "flexkane.report",
                              "flexkane.equations_document", "flexkane.result_cache", "flexkane.start_state",
                              "flexkane.analysis", "flexkane.c_export"]),
    ("sweep / post", ["flexkane.sweep", "flexkane.plots", "flexkane.plot_workers", "flexkane.animation"]),
    # the command line and the package root, which re-exports the public names on first use
    ("cli", ["flexkane.cli", "flexkane.commands", "flexkane.__main__", "flexkane"]),
]


def module_files() -> dict[str, pathlib.Path]:
    """Every module of the package by dotted name (a package by its own name)."""
    out = {}
    for path in sorted((SRC / PACKAGE).rglob("*.py")):
        parts = list(path.relative_to(SRC).with_suffix("").parts)
        if parts[-1] == "__init__":
            parts.pop()
        out[".".join(parts)] = path
    return out


MODULES = module_files()


def layer_of(module: str) -> int | None:
    """Index in :data:`LAYERS` of the longest listed prefix of ``module``, None if none is listed."""
    best, index = -1, None
    for k, (_, prefixes) in enumerate(LAYERS):
        for prefix in prefixes:
            if (module == prefix or module.startswith(prefix + ".")) and len(prefix) > best:
                best, index = len(prefix), k
    return index


@functools.lru_cache(maxsize=None)   # each module is read once for all the tests of this file
def imported_modules(module: str, path: pathlib.Path) -> list[tuple[str, int]]:
    """The flexkane modules ``module`` imports, with the line of each import."""
    is_package = path.name == "__init__.py"
    package = module if is_package else module.rpartition(".")[0]
    found = []
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"), str(path))):
        if isinstance(node, ast.Import):
            found += [(alias.name, node.lineno) for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")[:len(package.split(".")) - (node.level - 1)]
                target = ".".join(base + ([node.module] if node.module else []))
            else:
                target = node.module
            for alias in node.names:   # ``from . import numeric`` imports the module flexkane.kane.numeric
                submodule = f"{target}.{alias.name}"
                found.append((submodule if submodule in MODULES else target, node.lineno))
    return [(name, line) for name, line in found if name == PACKAGE or name.startswith(PACKAGE + ".")]


def test_every_module_has_a_layer():
    assert MODULES, "no module found"
    missing = sorted(m for m in MODULES if layer_of(m) is None)
    assert not missing, f"give these modules a layer in LAYERS: {missing}"


def test_no_module_imports_from_a_later_layer():
    problems = []
    for module, path in MODULES.items():
        own = layer_of(module)
        for target, line in imported_modules(module, path):
            other = layer_of(target)
            if other is not None and own is not None and other > own:
                problems.append(f"{path.relative_to(SRC)}:{line}: {module} ({LAYERS[own][0]}) imports "
                                f"{target} ({LAYERS[other][0]})")
    assert not problems, "imports against the direction of the layers:\n" + "\n".join(problems)


def test_the_library_does_not_import_the_package_root():
    """The root only re-exports public names; the version comes from flexkane._version."""
    offenders = [f"{module}:{line}" for module, path in MODULES.items() if module != PACKAGE
                 for target, line in imported_modules(module, path) if target == PACKAGE]
    assert not offenders, offenders


@pytest.mark.parametrize("source, expected", [
    ("from ..kane.chain import build_chain\n", "flexkane.kane.chain"),
    ("from . import numeric\n", "flexkane.model"),       # not a module of model/: the package itself
    ("import flexkane\n", "flexkane"),
])
def test_imports_are_resolved_as_python_does(tmp_path, source, expected):
    path = tmp_path / "validate.py"
    path.write_text(source)
    assert [name for name, _ in imported_modules("flexkane.model.validate", path)] == [expected]


def test_an_import_against_the_layers_is_found(tmp_path):
    path = tmp_path / "validate.py"
    path.write_text("def f():\n    from ..kane.chain import build_chain\n")
    targets = imported_modules("flexkane.model.validate", path)
    assert targets == [("flexkane.kane.chain", 2)]
    assert layer_of("flexkane.kane.chain") > layer_of("flexkane.model.validate")


def test_the_design_document_draws_these_layers():
    """docs/design.md shows the same layers, in the same order (latest on top)."""
    import re

    text = (SRC.parent / "docs" / "design.md").read_text(encoding="utf-8")
    section = text.split("## The package as layers", 1)[1].split("```")[1]
    drawn = [m.group(2) for m in re.finditer(r"^\s*(\d+)  (\S.*?)\s{2,}", section, re.MULTILINE)]
    assert drawn[::-1] == [name for name, _ in LAYERS]


def import_circles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The circles of a directed graph: its strongly connected components of two nodes or more, and the
    nodes that import themselves, each sorted, in sorted order (Tarjan's algorithm, without recursion)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    circles = []
    for root in sorted(graph):
        if root in index:
            continue
        work = [(root, iter(sorted(graph.get(root, ()))))]
        index[root] = low[root] = len(index)
        stack.append(root)
        on_stack.add(root)
        while work:
            node, successors = work[-1]
            for succ in successors:
                if succ not in index:
                    index[succ] = low[succ] = len(index)
                    stack.append(succ)
                    on_stack.add(succ)
                    work.append((succ, iter(sorted(graph.get(succ, ())))))
                    break
                if succ in on_stack:
                    low[node] = min(low[node], index[succ])
            else:
                work.pop()
                if work:
                    parent = work[-1][0]
                    low[parent] = min(low[parent], low[node])
                if low[node] == index[node]:
                    component = []
                    while True:
                        member = stack.pop()
                        on_stack.discard(member)
                        component.append(member)
                        if member == node:
                            break
                    if len(component) > 1 or node in graph.get(node, ()):
                        circles.append(sorted(component))
    return sorted(circles)


def test_the_circle_finder_finds_a_circle():
    graph = {"a": {"b"}, "b": {"c"}, "c": {"a", "d"}, "d": {"e"}, "e": {"d"}, "f": {"a"}, "g": {"g"}}
    assert import_circles(graph) == [["a", "b", "c"], ["d", "e"], ["g"]]
    assert import_circles({"a": {"b"}, "b": {"c"}, "c": set()}) == []


def test_no_module_takes_part_in_an_import_circle():
    """The modules import each other one way only, also inside the package of a layer: no module imports
    one that (at any depth) imports it back. Every import counts, at module level, in a function or under
    ``if TYPE_CHECKING:``; a package (its ``__init__``) is a module like the others."""
    graph = {module: {target for target, _ in imported_modules(module, path) if target in MODULES}
             for module, path in MODULES.items()}
    circles = import_circles(graph)
    listing = ["\n".join([f"circle of {len(circle)} modules:"]
                         + [f"  {MODULES[m].relative_to(SRC)} -> "
                            + ", ".join(sorted(t.rpartition('.')[2] for t in graph[m] if t in circle))
                            for m in circle])
               for circle in circles]
    assert not circles, "import circles:\n" + "\n".join(listing)
