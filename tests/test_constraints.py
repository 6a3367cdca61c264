"""The constraints file that ``make test`` installs with pins every dependency pyproject.toml names.

``constraints.txt`` holds the exact versions pip resolved from pyproject.toml's lower bounds the day
``make constraints`` was last run, so that a new release of a dependency cannot turn a fresh clone's
``make test`` red unnoticed. It must name every dependency of the base install and of the ``test`` and
``bench`` extras (else that one floats), pin each to one version (``==``), and never contradict a lower
bound of pyproject.toml (else the install fails, or the bound is a lie). ``packaging`` parses both:
pytest itself requires it, so it is present wherever the tests run.
"""

from __future__ import annotations

import re
import tomllib
from pathlib import Path

import pytest
from packaging.requirements import Requirement
from packaging.utils import canonicalize_name
from packaging.version import Version

ROOT = Path(__file__).resolve().parents[1]
PINNED_EXTRAS = ("test", "bench")


def pinned_versions(text: str) -> dict[str, Version]:
    """``{canonical name: version}`` of a constraints file; every line a comment or ``name==version``."""
    pins = {}
    for number, line in enumerate(text.splitlines(), start=1):
        line = line.strip()
        if not line or line.startswith("#"):
            continue
        requirement = Requirement(line)
        specifiers = list(requirement.specifier)
        assert len(specifiers) == 1 and specifiers[0].operator == "==", f"line {number} is not name==version: {line}"
        name = canonicalize_name(requirement.name)
        assert name not in pins, f"line {number} pins {name} a second time"
        pins[name] = Version(specifiers[0].version)
    return pins


def declared_requirements(project: dict, extras: tuple[str, ...]) -> list[Requirement]:
    """The base dependencies and those of ``extras``, with the project's own extras expanded."""
    own = canonicalize_name(project["name"])
    optional = project["optional-dependencies"]
    found, pending, seen = [], list(extras), set()
    found += [Requirement(text) for text in project["dependencies"]]
    while pending:
        extra = pending.pop()
        if extra in seen:
            continue
        seen.add(extra)
        for text in optional[extra]:
            requirement = Requirement(text)
            if canonicalize_name(requirement.name) == own:
                pending += sorted(requirement.extras)
            else:
                found.append(requirement)
    return found


def unpinned(requirements: list[Requirement], pins: dict[str, Version]) -> list[str]:
    return sorted({r.name for r in requirements if canonicalize_name(r.name) not in pins})


def contradicted(requirements: list[Requirement], pins: dict[str, Version]) -> list[str]:
    """The requirements whose bounds exclude the pinned version."""
    return sorted(f"{r} (pinned {pins[canonicalize_name(r.name)]})" for r in requirements
                  if canonicalize_name(r.name) in pins
                  and not r.specifier.contains(pins[canonicalize_name(r.name)], prereleases=True))


def load():
    project = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["project"]
    return project, pinned_versions((ROOT / "constraints.txt").read_text(encoding="utf-8"))


def test_every_dependency_of_the_base_test_and_bench_installs_is_pinned_within_its_bounds():
    project, pins = load()
    requirements = declared_requirements(project, PINNED_EXTRAS)
    assert {"numpy", "scipy", "sympy", "numba", "pytest", "exudyn", "dask"} <= {
        canonicalize_name(r.name) for r in requirements}      # the project's own extras were expanded
    missing, outside = unpinned(requirements, pins), contradicted(requirements, pins)
    assert not missing, f"constraints.txt does not pin {missing}: run make constraints"
    assert not outside, f"constraints.txt contradicts pyproject.toml: {outside}"
    assert canonicalize_name(project["name"]) not in pins


def test_a_missing_pin_and_a_pin_below_a_lower_bound_are_found():
    project, _ = load()
    base = declared_requirements(project, ())
    pins = pinned_versions("# a comment\nNumPy==1.25.2\nscipy==1.17.1\n")
    assert contradicted(base, pins) == ["numpy>=1.26 (pinned 1.25.2)"]
    assert "numba" in unpinned(base, pins) and "scipy" not in unpinned(base, pins)
    with pytest.raises(AssertionError, match="name==version"):
        pinned_versions("scipy>=1.11\n")


def test_every_install_of_the_makefile_uses_the_constraints_and_depends_on_them():
    makefile = (ROOT / "Makefile").read_text(encoding="utf-8")
    assert re.search(r"^CONSTRAINTS := constraints.txt$", makefile, re.M)
    assert re.search(r"^PIP_INSTALL = \$\(BIN\)/python -m pip install .*-c \$\(CONSTRAINTS\)$", makefile, re.M)
    # run, test, notebook and bench install with it; only pip itself is upgraded without
    recipes = [line.strip() for line in makefile.splitlines() if line.startswith("\t$(")]
    installs = [line for line in recipes if "pip install" in line or "$(PIP_INSTALL)" in line]
    assert installs[0] == "$(BIN)/python -m pip install --quiet --upgrade pip"
    assert len(installs) == 5 and all(line.startswith("$(PIP_INSTALL) -e ") for line in installs[1:]), installs
    # a changed constraints file reinstalls
    targets = re.findall(r"^\$\(VENV\)/\.installed[-\w]*: (.*)$", makefile, re.M)
    assert len(targets) == 4 and all("$(CONSTRAINTS)" in t.split("|")[0] for t in targets), targets
