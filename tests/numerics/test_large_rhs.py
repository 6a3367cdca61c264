"""Large right-hand sides: term tables and parts give the same numbers as SymPy."""

from __future__ import annotations

import numpy as np
import sympy as sp

from flexkane.numerics import generate_rhs_source, large_rhs


def coupled_masses(n=6):
    """n masses with a full symbolic stiffness K and a nonlinear damping D, and a time law.

    ``M = diag(m) + e x_i x_{i+1}`` (neighbours), ``f_i = sum_j (-K_ij x_j - D_ij u_j x_j^2)
    + a t sin(x_i)``: sums of 2 n + 1 terms, products of up to four factors, a factor (sin) that
    is not a product of symbols, zeros in M.
    """
    t = sp.Symbol("t")
    x = sp.symbols(f"x1:{n + 1}")
    u = sp.symbols(f"u1:{n + 1}")
    m = sp.symbols(f"m1:{n + 1}")
    K = sp.Matrix(n, n, lambda i, j: sp.Symbol(f"K_{min(i, j)}_{max(i, j)}"))
    D = sp.Matrix(n, n, lambda i, j: sp.Symbol(f"D_{i}_{j}"))
    a, e = sp.symbols("a e")
    mass = sp.Matrix(n, n, lambda i, j: m[i] if i == j else (e * x[i] * x[j] if abs(i - j) == 1 else 0))
    forcing = [sum(-K[i, j] * x[j] - D[i, j] * u[j] * x[j] ** 2 for j in range(n)) + a * t * sp.sin(x[i])
               for i in range(n)]
    constants = sorted(set().union(*(sp.Matrix(forcing).free_symbols, mass.free_symbols))
                       - set(x) - set(u) - {t}, key=lambda s: s.name)
    return t, x, u, constants, mass, forcing


def test_large_model_is_generated_with_term_tables_and_parts_and_equals_sympy(models, monkeypatch):
    t, x, u, constants, mass, forcing = coupled_masses()
    eom = models.eom(t, x, u, constants, u, mass, forcing)
    monkeypatch.setattr(large_rhs, "SPLIT_CHARS", 100)
    source = generate_rhs_source(eom)
    assert "rhs_table_sums(w, p, " in source and "def rhs_part1(" in source and "_COPY_M = " in source
    module = models.compile(eom)
    rng = np.random.default_rng(3)
    p = rng.uniform(0.5, 1.5, len(constants))
    args = [t, *x, *u, *constants]
    mass_f = sp.lambdify(args, mass, "numpy")
    forcing_f = sp.lambdify(args, sp.Matrix(forcing), "numpy")
    for time in (0.0, 0.7):
        y = rng.normal(scale=0.3, size=12)
        dy = np.empty(12)
        assert module.rhs(time, y, p, dy) == 0
        expected = np.linalg.solve(mass_f(time, *y, *p), forcing_f(time, *y, *p)).ravel()
        np.testing.assert_allclose(dy[:6], y[6:], rtol=0, atol=0)
        np.testing.assert_allclose(dy[6:], expected, rtol=1e-12, atol=1e-13)


def test_small_models_stay_written_out(double_pendulum_eom):
    source = generate_rhs_source(double_pendulum_eom)
    assert "table_sum" not in source and "_part0" not in source
