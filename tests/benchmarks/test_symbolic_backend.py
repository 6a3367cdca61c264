"""benchmarks/symbolic_backend.py: both symbolic backends give the same derivation, and the script
says what is missing when SymEngine is not installed."""

import importlib.util
import random
import subprocess
import sys
from pathlib import Path

import pytest

SCRIPT = Path(__file__).resolve().parents[2] / "benchmarks" / "symbolic_backend.py"


def load_script():
    pytest.importorskip("symengine")
    spec = importlib.util.spec_from_file_location("symbolic_backend", SCRIPT)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_sympy_and_symengine_derive_identical_inertia_forces_of_one_link():
    bench = load_script()
    _, sympy_out = bench.run_backend("sympy", 1, True)
    _, symengine_out = bench.run_backend("symengine", 1, True)
    # M (upper triangle, 3 speeds: 6 entries) and the remainder (3)
    assert len(sympy_out["kane"]) == len(symengine_out["kane"]) == 9
    report = bench.compare(sympy_out, symengine_out, exact=True, rng=random.Random(1))
    assert report == {stage: "identical" for stage in ("kane", "subs", "expand", "cse sympy", "cse symengine")}


def test_mass_matrix_of_one_link_is_the_rigid_hub_and_beam():
    """With the modes at rest, M_11 of the hub speed is the moment of inertia of hub, beam and payload
    about the joint axis (eq. 8.22): J + int rho (r + x)^2 dx + m_tip (r + L)^2 + J_tip."""
    bench = load_script()
    import sympy as sp

    _, out = bench.run_backend("sympy", 1, False)
    M11 = out["kane"][0]
    q = {sp.Symbol(f"q_link_1_{i}"): 0 for i in (1, 2)}
    r, L = sp.Symbol("r"), sp.Symbol("L")
    K = {a: sp.Symbol(f"K_1_{a}") for a in ("1_1", "1_x", "x_x")}  # int rho, int rho x, int rho x^2
    expected = sp.Symbol("J") + K["1_1"] * r ** 2 + 2 * K["1_x"] * r + K["x_x"] \
        + sp.Symbol("m_tip") * (r + L) ** 2 + sp.Symbol("J_tip")
    assert sp.expand(M11.xreplace(q) - expected) == 0


def test_script_without_symengine_exits_with_a_message():
    code = ("import sys, runpy; sys.modules['symengine'] = None; "
            f"runpy.run_path({str(SCRIPT)!r}, run_name='__main__')")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert done.returncode == 1
    assert "needs the symengine package" in done.stderr and "Traceback" not in done.stderr
