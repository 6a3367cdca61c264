"""A run whose equations, generated code and numbers are cached imports no SymPy, and writes what a
run that derives its equations afresh writes (issue 14 item 3; issue 16: one cached derive path,
outputs from the compiled outputs function).

Checked in fresh interpreters through ``sys.modules`` and by comparing the files: no clock involved.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np

SRC = Path(__file__).resolve().parents[2] / "src"
RUN = ["run", "falling-beam", "--t-end", "0.3", "--dt-out", "0.01", "--quiet", "--force"]
#: What a planar run does not need once its equations, code and numbers are cached: SymPy, the derivation
#: (planar and spatial engines, control inputs), code generation, linearization, sweeps, animation and
#: the controller loop.
UNNEEDED = ("sympy", "flexkane.kane", "flexkane.numerics.codegen", "flexkane.numerics.large_rhs",
            "flexkane.numerics.controller", "flexkane.analysis", "flexkane.sweep", "flexkane.animation",
            "flexkane.report", "flexkane.c_export")


def run_cli(out: Path, *extra: str) -> list[str]:
    """``flexkane run`` in a new interpreter (the test session's cache); return the modules of
    :data:`UNNEEDED` it imported (SymPy's among them)."""
    code = ("import json, sys\nfrom flexkane.cli import main\n"
            f"code = main({[*RUN, '--out', str(out), *extra]!r})\n"
            f"print(json.dumps([code, sorted(m for m in sys.modules if m.startswith({UNNEEDED!r}))]))")
    env = dict(os.environ, PYTHONPATH=str(SRC) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, timeout=600)
    assert done.returncode == 0, done.stderr
    code, sympy_modules = json.loads(done.stdout.strip().splitlines()[-1])
    assert code == 0
    return sympy_modules


def assert_same_files(a: Path, b: Path) -> None:
    """Equal files, results.npz array by array apart from its timing fields."""
    names = sorted(p.name for p in a.iterdir())
    assert names == sorted(p.name for p in b.iterdir())
    assert {"results.csv", "results.npz", "equations.md", "equations.tex", "energy.png", "q4.png"} <= set(names)
    for name in names:
        if name == "results.npz":
            with np.load(a / name) as x, np.load(b / name) as y:
                assert x.files == y.files
                for key in x.files:
                    if key != "timing":
                        np.testing.assert_array_equal(x[key], y[key], err_msg=key)
        else:
            assert (a / name).read_bytes() == (b / name).read_bytes(), name


def test_a_cached_run_imports_no_sympy_and_writes_what_a_fresh_derivation_writes(tmp_path):
    fresh = run_cli(tmp_path / "fresh", "--no-cache")        # derived afresh, nothing stored
    assert "sympy" in fresh and "flexkane.kane" in fresh
    run_cli(tmp_path / "first")                                # fills the cache (or finds it full)
    cached = run_cli(tmp_path / "cached")
    assert cached == []
    assert_same_files(tmp_path / "fresh", tmp_path / "cached")
    assert_same_files(tmp_path / "first", tmp_path / "cached")


def test_a_value_change_of_a_cached_structure_renders_no_equations(tmp_path):
    """``--set`` of a cached structure computes the new constants vector (SymPy loads the equations)
    but never imports the report: equations.md and .tex are the stored text with the new values, the
    same bytes as a run that derives and renders everything afresh."""
    settings = ["--set", "EI=40", "--set", "Iz=mR/7", "--no-plots"]
    fresh = run_cli(tmp_path / "fresh", *settings, "--no-cache")
    assert "flexkane.report" in fresh
    run_cli(tmp_path / "first", "--no-plots")                  # the structure's equations and text cached
    changed = run_cli(tmp_path / "changed", *settings)
    assert "flexkane.report" not in changed
    for name in ("equations.md", "equations.tex"):
        assert (tmp_path / "changed" / name).read_bytes() == (tmp_path / "fresh" / name).read_bytes(), name
    assert "| $EI$ | parameter |  |  | 40 |" in (tmp_path / "changed" / "equations.md").read_text(encoding="utf-8")
