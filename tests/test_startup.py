"""Instant start: ``import flexkane`` and the command line's --help and --version load none of the
heavy libraries (SymPy, SciPy, Numba, matplotlib); the public names still resolve on first use.

Checked in a fresh interpreter through ``sys.modules``: deterministic, no clock involved.
"""

import json
import subprocess
import sys

import pytest

from child_env import child_env

HEAVY = ("sympy", "scipy", "numba", "matplotlib")


def heavy_modules_after(code: str) -> dict:
    """Run ``code`` in a new interpreter; return the heavy top-level packages it imported and its output."""
    probe = (f"{code}\nimport json, sys\n"
             f"print(json.dumps(sorted({{m.split('.')[0] for m in sys.modules}} & set({HEAVY!r}))))")
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, env=child_env(), timeout=120)
    assert out.returncode == 0, out.stderr
    *printed, last = out.stdout.strip().splitlines()
    return {"heavy": json.loads(last), "printed": "\n".join(printed)}


def cli(*arguments: str) -> str:
    """Code that runs ``python -m flexkane ARGUMENTS`` in-process and keeps going after its exit."""
    return ("import runpy, sys\n"
            f"sys.argv = ['flexkane', *{list(arguments)!r}]\n"
            "try:\n    runpy.run_module('flexkane', run_name='__main__', alter_sys=True)\n"
            "except SystemExit:\n    pass\n")


def test_import_flexkane_loads_no_heavy_library():
    found = heavy_modules_after("import flexkane\nprint(flexkane.__version__)")
    assert found["heavy"] == []
    assert found["printed"].strip() == __import__("flexkane").__version__


@pytest.mark.parametrize("arguments", [("--help",), ("--version",), ("run", "--help"), ("check", "--help")])
def test_help_and_version_load_no_heavy_library(arguments):
    found = heavy_modules_after(cli(*arguments))
    assert found["heavy"] == []
    assert "flexkane" in found["printed"]


def test_public_names_resolve_on_first_use():
    import flexkane
    import flexkane.analysis.eigen  # noqa: F401 - the subpackage of analyses has its own name
    from flexkane.derivation_cache import derive   # the package derive: the cached one
    from flexkane.analysis.linearization import linearize

    assert flexkane.derive is derive
    assert flexkane.linearize is linearize and callable(flexkane.linearize)
    assert flexkane.analysis.linearize is linearize and callable(flexkane.analysis.load_control)
    assert set(flexkane.__all__) <= set(dir(flexkane))
    with pytest.raises(AttributeError):
        flexkane.no_such_name  # noqa: B018


def test_modes_help_still_lists_every_family(capsys):
    from flexkane.cli import main
    from flexkane.modes import family_names

    with pytest.raises(SystemExit):
        main(["modes", "--help"])
    text = "".join(capsys.readouterr().out.split())          # help wraps lines, also at hyphens
    assert ",".join(family_names()) in text


def test_check_of_every_builtin_model_loads_no_scipy_numba_or_matplotlib():
    """``check`` validates with the expression language and the chain's coordinate names: none of the
    numerical or plotting libraries."""
    from flexkane.builtin import builtin_names

    code = ("from flexkane.cli import main\n"
            f"codes = [main(['check', name]) for name in {list(builtin_names())!r}]\n"
            "print(codes)")
    found = heavy_modules_after(code)
    assert found["printed"].splitlines()[-1] == str([0] * len(builtin_names()))
    assert set(found["heavy"]) <= {"sympy"}


def _uses_expression_shapes(name: str) -> bool:
    from flexkane.builtin import builtin_model

    model = builtin_model(name)
    return any(spec is not None and spec.family == "expression"
               for beam in model.beams.values() for spec in (beam.shape, beam.axial_shape))


@pytest.mark.parametrize("name", __import__("flexkane.builtin", fromlist=["builtin_names"]).builtin_names())
def test_check_of_a_builtin_model_loads_no_sympy(name):
    """Values, time laws, distributed loads, parameters, shape families and coordinate names are checked
    without SymPy; only shape functions given as expressions of xi (family ``expression``, differentiated
    to check their boundary conditions) need it."""
    found = heavy_modules_after(cli("check", name))
    assert f"{name}: valid" in found["printed"]
    assert found["heavy"] == (["sympy"] if _uses_expression_shapes(name) else [])
