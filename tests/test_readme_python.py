"""Every Python call in the README works as written.

* Each ```python block runs, in the README's order, in one namespace per section (``## ...``), in a
  temporary directory; the models it compiles go to the session's temporary cache
  (``FLEXKANE_CACHE_DIR``, tests/conftest.py). After a section's blocks, every inline code span of
  that section that is a Python expression of the names the blocks defined (``model.with_values(...)``,
  ``results.to_dataframe()``, ``results.t``) is evaluated there too, as a doctest would, and so is
  every dotted name in the blocks' comments (``eom.F_r_star``).
* Every dotted call in an inline code span (``flexkane.analysis.load_control(path)``,
  ``linear.state_space()``, ``Results.to_dataframe()``) and every ``flexkane.`` name names something
  that exists and, for a call, is callable: modules are imported and attributes looked up, nothing is
  called. A name on an instance (``linear.``) is looked up on the class the README means by it
  (:func:`instance_classes`; a new instance name must be added there).
"""

from __future__ import annotations

import ast
import importlib
import re
import tokenize
from io import StringIO
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
README = (ROOT / "README.md").read_text(encoding="utf-8")
FENCE = re.compile(r"^[ ]*```(\w*)\n(.*?)^[ ]*```[ ]*$", re.M | re.S)
#: A dotted name, and whether a call follows it: ``flexkane.analysis.linearize(``.
DOTTED = re.compile(r"(?<![\w.\[/\"'-])([A-Za-z_]\w*(?:\.[A-Za-z_]\w*)+)(\()?")


def instance_classes() -> dict:
    """The class of each instance and class name the README's prose uses (``linear`` for a linear model)."""
    from flexkane.analysis import LinearModel, Linearization
    from flexkane.model import Model
    from flexkane.results import Results

    return {"model": Model, "results": Results, "linear": LinearModel,
            "Results": Results, "LinearModel": LinearModel, "Linearization": Linearization}


def sections(text: str) -> list[tuple[str, int, str]]:
    """``(heading, first line number, text)`` of each ``## `` section, fenced blocks kept whole."""
    found, heading, start, lines, fenced = [], "(top)", 1, [], False
    for number, line in enumerate(text.splitlines(keepends=True), start=1):
        if line.lstrip().startswith("```"):
            fenced = not fenced
        if line.startswith("## ") and not fenced:
            found.append((heading, start, "".join(lines)))
            heading, start, lines = line[3:].strip(), number, []
        lines.append(line)
    found.append((heading, start, "".join(lines)))
    return found


def python_blocks(section: str, first_line: int) -> list[tuple[int, str]]:
    """``(line number in README.md of its first line, source)`` of each ```python block of a section."""
    return [(first_line + section[:m.start()].count("\n") + 1, m.group(2))
            for m in FENCE.finditer(section) if m.group(1) == "python"]


def inline_code(text: str) -> list[str]:
    """The inline code spans of Markdown text (fenced blocks left out); a span may wrap lines."""
    prose = FENCE.sub("", text)
    return [span.replace("\n", " ") for span in re.findall(r"`([^`]+)`", prose)]


def resolve(dotted: str):
    """The object a dotted name of an importable root names: modules imported, attributes looked up."""
    parts = dotted.split(".")
    obj = importlib.import_module(parts[0])
    for k, part in enumerate(parts[1:], start=2):
        try:
            obj = getattr(obj, part)
        except AttributeError:
            obj = importlib.import_module(".".join(parts[:k]))
    return obj


def free_names(expression: ast.Expression) -> set[str]:
    return {node.id for node in ast.walk(expression) if isinstance(node, ast.Name)}


def as_expression(span: str) -> ast.Expression | None:
    try:
        return ast.parse(span, mode="eval")
    except SyntaxError:
        return None


def comment_names(source: str) -> set[str]:
    """Dotted names in the comments of Python source (``eom.mass_matrix``)."""
    comments = [tok.string for tok in tokenize.generate_tokens(StringIO(source).readline)
                if tok.type == tokenize.COMMENT]
    return {m.group(1) for text in comments for m in DOTTED.finditer(text)}


RUNNABLE = [(heading, first, text) for heading, first, text in sections(README) if python_blocks(text, first)]


def test_sections_split_at_level_two_headings_outside_fenced_blocks():
    text = "# t\nintro\n## A\n```python\nx = 1\n## not a heading\n```\n### A.1\n## B\n`b.c()`\n"
    found = sections(text)
    assert [(heading, first) for heading, first, _ in found] == [("(top)", 1), ("A", 3), ("B", 9)]
    assert python_blocks(found[1][2], found[1][1]) == [(5, "x = 1\n## not a heading\n")]
    assert inline_code(found[1][2]) == [] and inline_code(found[2][2]) == ["b.c()"]
    assert "Usage" in [heading for heading, _, _ in RUNNABLE]     # the README's Python API example


@pytest.mark.parametrize("heading, first_line, text", RUNNABLE, ids=[h for h, _, _ in RUNNABLE])
def test_python_blocks_of_a_section_run_and_its_inline_expressions_evaluate(heading, first_line, text,
                                                                         tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    namespace = {"__name__": f"readme_{first_line}"}
    blocks = python_blocks(text, first_line)
    for line, source in blocks:
        exec(compile(source, f"README.md:{line}", "exec"), namespace)   # the README's own code
    evaluated = []
    for span in inline_code(text):
        expression = as_expression(span)
        if expression is not None and free_names(expression) and free_names(expression) <= namespace.keys():
            eval(compile(expression, f"README.md ({heading}): {span}", "eval"), namespace)
            evaluated.append(span)
    for dotted in sorted({name for _, source in blocks for name in comment_names(source)}):
        root, *attributes = dotted.split(".")
        obj = namespace[root] if root in namespace else resolve(root)
        for attribute in attributes:
            obj = getattr(obj, attribute)
    if heading == "Usage":
        assert 'model.with_values({"beams.B.EI": 20, "u3": 2})' in evaluated
        assert "results.to_dataframe()" in evaluated and "results.y" in evaluated


def dotted_names() -> list[tuple[str, bool]]:
    """``(name, called)`` of every dotted call and every ``flexkane.`` name in inline code."""
    found = {}
    for span in inline_code(README):
        for m in DOTTED.finditer(span):
            name, called = m.group(1), m.group(2) is not None
            if called or name.startswith("flexkane."):
                found[name] = found.get(name, False) or called
    return sorted(found.items())


def test_every_dotted_name_in_inline_code_exists_and_every_call_is_callable():
    names = dotted_names()
    assert sum(called for _, called in names) >= 10, names          # the README's calls were found
    classes = instance_classes()
    unresolved = []
    for name, called in names:
        root, *attributes = name.split(".")
        try:
            if root in classes:
                obj = classes[root]
                for attribute in attributes:
                    obj = getattr(obj, attribute)
            else:
                obj = resolve(name)
        except (ImportError, AttributeError) as exc:
            unresolved.append(f"{name}: {exc}")
            continue
        if called and not callable(obj):
            unresolved.append(f"{name}: not callable")
    assert not unresolved, unresolved


def test_the_analyses_are_named_by_their_package_and_linearize_is_the_function():
    import flexkane

    assert "flexkane.linearize." not in README            # the package is flexkane.analysis
    assert callable(flexkane.linearize) and flexkane.linearize is resolve("flexkane.analysis.linearize")
    assert resolve("flexkane.analysis.load_control").__module__ == "flexkane.analysis.linear_model"
