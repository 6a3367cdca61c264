"""The README's promises about the package itself: every built-in model is listed, the extras it
names exist, and its sweep example varies something the metric depends on."""

import re
import tomllib
from pathlib import Path

import pytest

import flexkane

ROOT = Path(__file__).resolve().parents[1]
README = (ROOT / "README.md").read_text()


def test_every_built_in_model_is_listed_in_the_usage_and_the_table():
    usage = README[README.index("`MODEL` is a built-in model"):README.index("or the path of a model file")]
    table = README[README.index("## Built-in examples"):]
    for name in flexkane.builtin_names():
        assert f"`{name}`" in usage, name
        assert f"`{name}`" in table.split("\n\n")[1] or f"`{name}`," in table, name


def test_the_extras_named_in_the_readme_exist():
    extras = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["optional-dependencies"]
    for name in set(re.findall(r"flexkane\[(\w+)\]", README)):
        assert name in extras, name
    assert "make notebook" in README and "notebook:" in (ROOT / "Makefile").read_text()


@pytest.mark.slow
def test_the_sweep_example_gives_a_metric_that_depends_on_the_swept_parameter(tmp_path):
    from flexkane.cli import main
    from flexkane.sweep import read_table

    command = re.search(r"\$ flexkane (sweep [^\n]+)", README).group(1).split()
    out = tmp_path / "sweep"
    argv = [a if not a.startswith("out/") else str(out) for a in command] + ["--workers", "1", "--quiet"]
    assert main(argv) == 0
    values = [row["max_abs_tip_link"] for row in read_table(out, as_rows=True)]
    assert all(a > 1.2 * b for a, b in zip(values, values[1:]))     # stiffer link, smaller deflection
    assert abs(values[0] - 0.110) < 0.001 and abs(values[-1] - 0.0151) < 0.0002


def _anchor(heading: str) -> str:
    """The anchor a Markdown renderer (GitHub's rule) gives a heading: lower case, punctuation but - and _
    dropped, spaces as -."""
    return re.sub(r"[^\w\- ]", "", heading.strip().lower()).replace(" ", "-")


def test_the_table_of_contents_lists_every_section_in_order_with_working_links():
    headings, fenced = [], False
    for line in README.splitlines():
        if line.startswith("```"):
            fenced = not fenced
        elif not fenced and re.match(r"#{2,3} ", line) and line != "## Contents":
            headings.append(line.split(" ", 1)[1])
    contents = README[README.index("## Contents"):README.index("## Quick start")]
    entries = re.findall(r"^ *- \[(.+)\]\(#([^)]+)\)$", contents, flags=re.M)
    assert [title for title, _ in entries] == headings
    assert all(link == _anchor(title) for title, link in entries)
