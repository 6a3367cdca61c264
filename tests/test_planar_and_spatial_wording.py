"""flexkane says what it is: planar and spatial chains.

The one-line descriptions (``pyproject.toml``, ``flexkane --help``, the README's first line) name
both, the C header names the exported chain's kind, and the equations report of a spatial chain cites
the chapter's planar equations (8.22-8.36) only as what its own equations generalize, while a planar
chain's report cites them as its own, unchanged.
"""

from __future__ import annotations

import re
import tomllib
from pathlib import Path

import pytest

import flexkane
from flexkane.cli import build_parser
from flexkane.report import equations_latex, equations_markdown
from spatial_beam_models import clamped_spatial_beam

ROOT = Path(__file__).resolve().parents[1]
#: A citation of a numbered equation of the chapter: "eq. 8.23", "eqs. 8.22, 8.23, 8.28-8.35".
CITATION = re.compile(r"eqs?\. 8\.\d+")


def says_planar_and_spatial(text: str) -> bool:
    return bool(re.search(r"\bplanar and spatial\b", text)) and "planar kinematic chains with" not in text


def test_the_one_line_descriptions_say_planar_and_spatial():
    project = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["project"]
    assert says_planar_and_spatial(project["description"])
    assert says_planar_and_spatial(build_parser().format_help())
    readme = (ROOT / "README.md").read_text(encoding="utf-8").splitlines()
    assert readme[0] == "# flexkane" and says_planar_and_spatial(readme[2])


@pytest.fixture(scope="module")
def spatial_beam():
    """A clamped spatial beam, one mode per bending plane and one in torsion (derives in seconds)."""
    model = flexkane.loads_model(clamped_spatial_beam("wording-spatial-beam", """
n_modes_y = 1
n_modes_z = 1
n_torsion = 1
"""))
    eom = flexkane.derive(model)
    return eom, eom.constant_values()


def citing_lines(text: str) -> list[str]:
    return [line for line in text.splitlines() if CITATION.search(line)]


def test_a_spatial_report_cites_the_planar_equations_only_as_what_it_generalizes(spatial_beam):
    eom, values = spatial_beam
    assert eom.model.dimensions == 3
    # Markdown: Kane's equations, the forces' heading, the grouping of eq. 8.23, the modal constants;
    # LaTeX: the first two
    for text, count in ((equations_markdown(eom, values), 4), (equations_latex(eom, values), 2)):
        lines = citing_lines(text)
        assert len(lines) == count, lines
        for line in lines:
            # every citation in the line is preceded by "planar" (the planar eq. ..., the planar ones below eq. ...)
            for match in CITATION.finditer(line):
                assert "planar" in line[:match.start()], line
        assert "Generalized inertia and active forces (the spatial generalization of the planar eqs. 8.22, " in text
        assert "(eq. 8.36)" not in text and "(eqs. 8.22" not in text


def test_a_planar_report_cites_the_chapter_equations_as_its_own():
    eom = flexkane.derive(flexkane.builtin_model("falling-beam").with_modes(1))
    text = equations_markdown(eom, eom.constant_values())
    assert "$F^*_r + F_r = 0$ (eq. 8.36) for every" in text
    assert "## Generalized inertia and active forces (eqs. 8.22, 8.23, 8.28-8.35)" in text
    assert "Modal constants (below eq. 8.22 and eq. 8.32;" in text
    assert not [line for line in citing_lines(text) if "planar" in line or "generalization" in line]


def test_the_c_header_names_the_kind_of_chain(spatial_beam, tmp_path):
    for model, kind in ((flexkane.builtin_model("pendulum-beam").with_modes(1), "planar"),
                        (spatial_beam[0].model, "spatial")):
        flexkane.export_c(model, tmp_path / kind)
        header = next((tmp_path / kind).glob("*.h")).read_text(encoding="utf-8")
        assert f" * Kane's equations of a {kind} chain: q' = qdot(t, q, u)" in header
