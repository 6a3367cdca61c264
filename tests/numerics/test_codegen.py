"""Generated source: its header, its arithmetic against SymPy, its L D L^T solve, its errors."""

from __future__ import annotations

import re

import numpy as np
import pytest
import sympy as sp

from flexkane.numerics import evaluate_outputs, generate_outputs_source, generate_rhs_source
from flexkane.numerics.linear_algebra import ldl_solve, lu_factor, lu_solve


def test_rhs_source_documents_state_and_constant_order(double_pendulum_eom):
    source = generate_rhs_source(double_pendulum_eom)
    assert "#   y[0] = q1" in source and "#   y[3] = u2" in source
    assert "#   p[4] = g" in source
    assert "STATE_NAMES = ('q1', 'q2', 'u1', 'u2')" in source
    assert "@njit(cache=True" in source


def test_rhs_equals_sympy_solution_of_mass_matrix_and_forcing(double_pendulum_eom,
                                                             double_pendulum_module):
    eom = double_pendulum_eom
    rng = np.random.default_rng(1)
    p = np.array([1.0, 1.5, 1.0, 0.7, 9.81])
    args = [*eom.q, *eom.u, *eom.constants]
    mass = sp.lambdify(args, eom.mass_matrix, "numpy")
    forcing = sp.lambdify(args, eom.forcing, "numpy")
    for _ in range(5):
        y = rng.normal(size=4)
        dy = np.empty(4)
        assert double_pendulum_module.rhs(0.0, y, p, dy) == 0
        expected = np.linalg.solve(mass(*y, *p), forcing(*y, *p)).ravel()
        np.testing.assert_allclose(dy[:2], y[2:])
        np.testing.assert_allclose(dy[2:], expected, rtol=1e-12, atol=1e-12)


def test_ldl_solve_matches_numpy_on_random_spd_matrices():
    rng = np.random.default_rng(0)
    for n in (1, 3, 12):
        a = rng.normal(size=(n, n))
        spd = a @ a.T + n * np.eye(n)
        b = rng.normal(size=n)
        x = b.copy()
        assert ldl_solve.py_func(np.triu(spd), x) == 0  # upper triangle only is read
        np.testing.assert_allclose(x, np.linalg.solve(spd, b), rtol=1e-12)


def test_ldl_solve_flags_singular_and_non_finite_matrices():
    x = np.ones(2)
    assert ldl_solve.py_func(np.array([[1.0, 1.0], [1.0, 1.0]]), x) == 4
    assert np.all(np.isnan(x))
    assert ldl_solve.py_func(np.array([[np.nan, 0.0], [0.0, 1.0]]), np.ones(2)) == 2


def test_lu_solve_matches_numpy_for_real_and_complex_matrices():
    rng = np.random.default_rng(2)
    for dtype in (np.float64, np.complex128):
        a = rng.normal(size=(6, 6)).astype(dtype)
        if dtype is np.complex128:
            a = a + 1j * rng.normal(size=(6, 6))
        b = rng.normal(size=6).astype(dtype)
        lu, piv, x = a.copy(), np.empty(6, np.int64), b.copy()
        assert lu_factor.py_func(lu, piv) == 0
        lu_solve.py_func(lu, piv, x)
        np.testing.assert_allclose(x, np.linalg.solve(a, b), rtol=1e-10)
    assert lu_factor.py_func(np.zeros((2, 2)), np.empty(2, np.int64)) == 1


def test_time_laws_with_piecewise_min_max_abs_compile_and_evaluate(models):
    t, x, v, k = sp.symbols("t x v k")
    drive = sp.Piecewise((t, t < 1), (2 - t, t < 2), (0, True))
    forcing = [-k * x + sp.Max(-1, sp.Min(1, drive)) + sp.Abs(v) * sp.tanh(v) + sp.sqrt(1 + t)]
    eom = models.eom(t, [x], [v], [k], [v], [[2 + sp.exp(-t)]], forcing)
    module = models.compile(eom)
    dy = np.empty(2)
    for time in (0.5, 1.5, 3.0):
        assert module.rhs(time, np.array([0.2, -0.3]), np.array([4.0]), dy) == 0
        law = time if time < 1 else (2 - time if time < 2 else 0.0)
        expected = (-0.8 + law + 0.3 * np.tanh(-0.3) + np.sqrt(1 + time)) / (2 + np.exp(-time))
        assert dy[1] == pytest.approx(expected, rel=1e-14)


def test_more_speeds_than_unrolled_use_the_ldl_loop(models):
    eom = models.stiff_chain(9)
    source = generate_rhs_source(eom)
    # its mass matrix diag(m) is constant: factored once per run, solved by block elimination
    # (tests/numerics/test_constant_block.py); a state-dependent one gets ldl_solve(_M, ...)
    assert "schur_solve(_M" in source
    module = models.compile(eom)
    p = np.concatenate([np.arange(1.0, 10.0), np.full(9, 10.0), np.full(9, 0.1)])
    y = np.linspace(-1, 1, 18)
    dy = np.empty(18)
    assert module.rhs(0.0, y, p, dy) == 0
    q, u = y[:9], y[9:]
    k, c, m = p[9:18], p[18:], p[:9]
    f = -k * (q - np.r_[0, q[:-1]]) - c * (u - np.r_[0, u[:-1]])
    f[:-1] += k[1:] * (q[1:] - q[:-1]) + c[1:] * (u[1:] - u[:-1])
    np.testing.assert_allclose(dy[9:], f / m, rtol=1e-12)


def test_outputs_with_accelerations_are_evaluated_over_many_samples(oscillator_module):
    t = np.linspace(0, 1, 50)
    y = np.column_stack([np.cos(t), -np.sin(t)])
    values = evaluate_outputs(oscillator_module, t, y, np.array([2.0, 2.0]))
    np.testing.assert_allclose(values["energy"], 1.0, rtol=1e-14)
    np.testing.assert_allclose(values["x2"], 2 * np.cos(t))
    np.testing.assert_allclose(values["spring_force"], 2.0 * np.cos(t), rtol=1e-14)


def test_undeclared_symbol_is_reported_by_name(models):
    t, x, v, k, mystery = sp.symbols("t x v k mystery")
    eom = models.eom(t, [x], [v], [k], [v], [[1]], [-k * x * mystery])
    with pytest.raises(ValueError, match="mystery"):
        generate_rhs_source(eom)


def test_unsupported_function_is_reported(models):
    t, x, v = sp.symbols("t x v")
    eom = models.eom(t, [x], [v], [], [v], [[1]], [sp.besselj(0, x)])
    with pytest.raises(ValueError, match="besselj"):
        generate_rhs_source(eom)


def test_symbol_names_that_clash_with_arguments_are_renamed(models):
    t, y, p, lam = sp.symbols("t y p lambda")
    eom = models.eom(t, [y], [p], [lam], [p], [[1]], [-lam * y])
    source = generate_rhs_source(eom)
    compile(source, "<generated>", "exec")
    assert "s_y = y[0]" in source and "s_lambda = p[0]" in source
    outputs = generate_outputs_source({"e": p ** 2 + lam * y ** 2}, eom)
    compile(outputs, "<generated>", "exec")


def test_every_generated_constant_is_a_float(models):
    """``(3*t)**50`` is 3**50 * t**50: an integer beyond int64 that Numba refused to compile."""
    from flexkane.numerics.codegen import _MathPrinter

    t, x = sp.symbols("t x")
    printer = _MathPrinter()
    assert printer.doprint((3 * t) ** 50) == f"{float(3 ** 50)!r}*t**50"
    assert printer.doprint(2 * x + 1) == "2.0*x + 1.0"
    assert printer.doprint(x / 3) == f"({1 / 3!r})*x"
    assert printer.doprint(x ** 2) == "x**2" and printer.doprint(x ** 100) == "x**100.0"
    # Numba's integer power raises ZeroDivisionError at 0 for a negative exponent: a division
    # gives inf instead, which the integrators report as a non-finite derivative
    assert printer.doprint(x ** -3) == "(1.0/x**3)"
    eom = models.eom(t, [x], [sp.Symbol("v")], [], [sp.Symbol("v")], [[1]], [(3 * t) ** 50])
    source = generate_rhs_source(eom)
    assert not re.search(r"(?<![\w.])\d{19,}(?![\d.e])", source)  # no integer literal beyond int64


def test_generated_functions_load_only_the_constants_and_state_entries_they_read(models):
    """Unused loads cost Numba typing and lowering: the rhs and the outputs read only what they use,
    and give the same numbers."""
    t, x, v, m, k, unused = sp.symbols("t x v m k unused_constant")
    eom = models.eom(t, [x], [v], [m, k, unused], [v], [[m]], [-k * x])
    rhs = generate_rhs_source(eom)
    assert "m = p[0]" in rhs and "k = p[1]" in rhs and "unused_constant" not in rhs.split("def rhs")[1]
    outputs = generate_outputs_source({"kinetic": m * v ** 2 / 2, "time": t}, eom)
    body = outputs.split("def outputs")[1]
    assert "m = _p[0]" in body and "v = _Y[_k, 1]" in body and "t = _t[_k]" in body
    assert "k = _p[" not in body and "x = _Y[" not in body and "unused_constant" not in body
    none = generate_outputs_source({}, eom, name="nothing")
    namespace = {}
    exec(compile(none.replace("@njit(cache=True, error_model=\"numpy\")", ""), "<generated>", "exec"),
         {"np": np, "math": __import__("math")}, namespace)
    assert namespace["nothing"](np.zeros(3), np.zeros((3, 2)), np.ones(3)).shape == (3, 0)
