"""The constant block of the mass matrix: found symbolically, factored once per run, solved by a
Schur complement that agrees with the plain L D L^T solve to round-off."""

from __future__ import annotations

import importlib
import types

import numpy as np
import pytest
import sympy as sp

import flexkane
from flexkane.numerics import codegen, constant_block, generate_rhs_source, integrate, large_rhs
from flexkane.numerics.constant_block import constant_block as find_block
from flexkane.numerics.constant_block import constant_intermediates, prepared_parameters
from flexkane.numerics.integrate import Status
from flexkane.numerics.linear_algebra import constant_block_factor, ldl_solve, schur_solve


def modal_arm(n_rigid=2, n_modes=10, stiffening=False):
    """Rigid coordinates ``x`` carrying modal coordinates ``e`` (a beam's structure, made up).

    ``M = [[M_rr(x, e), M_rc(x)], [M_cr(x), G]]`` with ``M_rr = diag(J_a + sum_j e_j^2)
    + m cos(x_1 - x_2)`` off the diagonal, ``M_rc[a, j] = E_j cos(x_a)`` and the modal mass
    ``G_ij`` (constants); with ``stiffening``, ``G_ij + D_ij x_1^2`` instead, as geometric
    stiffening makes the modal block depend on the state. Forcing: gravity-like ``-g sin(x_a)``,
    modal springs ``-K_j e_j``, a time law and centrifugal terms ``u_1^2 sum_j G_ij e_j``.
    """
    t = sp.Symbol("t")
    x = sp.symbols(f"x1:{n_rigid + 1}")
    e = sp.symbols(f"e1:{n_modes + 1}")
    ux = sp.symbols(f"ux1:{n_rigid + 1}")
    ue = sp.symbols(f"ue1:{n_modes + 1}")
    J = sp.symbols(f"J1:{n_rigid + 1}")
    E = sp.symbols(f"E1:{n_modes + 1}")
    K = sp.symbols(f"K1:{n_modes + 1}")
    G = sp.Matrix(n_modes, n_modes, lambda i, j: sp.Symbol(f"G_{min(i, j) + 1}_{max(i, j) + 1}"))
    D = sp.Matrix(n_modes, n_modes, lambda i, j: sp.Symbol(f"D_{min(i, j) + 1}_{max(i, j) + 1}"))
    m, g, a = sp.symbols("m g a")
    n = n_rigid + n_modes
    M = sp.zeros(n, n)
    for i in range(n_rigid):
        M[i, i] = J[i] + sum(ej ** 2 for ej in e)
        for k in range(i + 1, n_rigid):
            M[i, k] = M[k, i] = m * sp.cos(x[i] - x[k])
        for j in range(n_modes):
            M[i, n_rigid + j] = M[n_rigid + j, i] = E[j] * sp.cos(x[i])
    for i in range(n_modes):
        for j in range(n_modes):
            M[n_rigid + i, n_rigid + j] = G[i, j] + (D[i, j] * x[0] ** 2 if stiffening else 0)
    forcing = [-g * sp.sin(xa) + a * sp.sin(t) for xa in x]
    forcing += [-K[i] * e[i] + ux[0] ** 2 * sum(G[i, j] * e[j] for j in range(n_modes))
                for i in range(n_modes)]
    constants = sorted((M.free_symbols | sp.Matrix(forcing).free_symbols) - set(x) - set(e)
                       - set(ux) - set(ue) - {t}, key=lambda s: s.name)
    return types.SimpleNamespace(t=t, q=[*x, *e], u=[*ux, *ue], constants=constants,
                                 qdot=sp.Matrix([*ux, *ue]), mass_matrix=M,
                                 forcing=sp.Matrix(forcing))


def modal_arm_constants(eom, rng, modal_mass_scale=1.0):
    """Numbers for :func:`modal_arm`: an SPD modal mass, a positive definite M."""
    n_modes = sum(1 for s in eom.constants if s.name.startswith("K"))
    A = rng.normal(size=(n_modes, n_modes))
    G = modal_mass_scale * (A @ A.T / n_modes + np.eye(n_modes))
    values = {}
    for s in eom.constants:
        name = s.name
        if name.startswith("G_"):
            i, j = (int(k) - 1 for k in name[2:].split("_"))
            values[name] = G[i, j]
        elif name.startswith("D_"):
            values[name] = 0.1 * (1.0 if name.split("_")[1] == name.split("_")[2] else 0.0)
        elif name.startswith("J"):
            values[name] = 5.0
        elif name.startswith("E"):
            values[name] = rng.uniform(-0.3, 0.3)
        elif name.startswith("K"):
            values[name] = rng.uniform(10.0, 100.0)
        else:
            values[name] = {"m": 0.5, "g": 9.81, "a": 0.7}[name]
    return np.array([values[s.name] for s in eom.constants])


def lambdified_solution(eom):
    args = [eom.t, *eom.q, *eom.u, *eom.constants]
    mass = sp.lambdify(args, eom.mass_matrix, "numpy")
    forcing = sp.lambdify(args, eom.forcing, "numpy")
    return lambda t, y, p: np.linalg.solve(mass(t, *y, *p), forcing(t, *y, *p)).ravel()


@pytest.fixture(scope="module")
def arm():
    return modal_arm()


@pytest.fixture(scope="module")
def arm_modules(arm, models):
    """The modal arm compiled three ways: block solve, plain L D L^T, block solve in parts."""
    block = models.compile(arm)
    mp = pytest.MonkeyPatch()
    mp.setattr(constant_block, "block_is_cheaper", lambda c, n: False)
    plain = models.compile(arm)
    mp.undo()
    mp.setattr(large_rhs, "SPLIT_CHARS", 200)
    mp.setattr(codegen, "_has_long_sums", lambda exprs: True)   # its sums are short: split anyway
    parts = models.compile(arm)
    source = generate_rhs_source(arm)
    mp.undo()
    return types.SimpleNamespace(block=block, plain=plain, parts=parts, parts_source=source)


def test_modal_block_is_found_in_the_symbolic_mass_matrix(arm):
    assert find_block(arm, arm.mass_matrix) == list(range(2, 12))
    assert find_block(modal_arm(stiffening=True), modal_arm(stiffening=True).mass_matrix) == []


def test_intermediates_count_as_constant_only_if_their_expressions_are():
    x, k, m = sp.symbols("x k m")
    a, b, c = sp.symbols("a b c")
    eom = types.SimpleNamespace(constants=[k, m], intermediates=[(a, 2 * m), (b, a * x), (c, a + k)])
    assert constant_intermediates(eom) == {a: 2 * m, c: 2 * m + k}
    mass = sp.Matrix([[c, 0, b], [0, a, 0], [b, 0, m + x]])
    assert find_block(eom, mass) == [0, 1]
    # a coupling that depends on the state splits the block: the first largest one is kept
    assert find_block(types.SimpleNamespace(constants=[k, m]), sp.Matrix([[m, x], [x, k]])) == [0]
    assert find_block(types.SimpleNamespace(constants=[k, m]), sp.Matrix([[m * x, 0], [0, x]])) == []


def test_beam_modal_mass_is_constant_unless_geometric_stiffening():
    beam = flexkane.derive(flexkane.builtin_model("falling-beam-exact").with_modes(3))
    # speeds x', y', theta', eta_1..3: only theta' has a mass entry depending on q (with y')
    assert find_block(beam, beam.mass_matrix) == [0, 1, 3, 4, 5]
    linear = flexkane.derive(flexkane.builtin_model("spin-up-linear"))
    assert find_block(linear, linear.mass_matrix) == [0, 1, 2, 3]
    stiffened = flexkane.derive(flexkane.builtin_model("spin-up"))  # geometric stiffening
    assert find_block(stiffened, stiffened.mass_matrix) == []


def test_block_solve_costs_fewer_operations_only_for_a_large_block():
    assert constant_block.block_is_cheaper(42, 43)   # falling-beam-exact, 40 modes
    assert not constant_block.block_is_cheaper(1, 43)
    assert not constant_block.block_is_cheaper(0, 10)
    assert constant_block.block_operations(42, 1) < constant_block.plain_operations(43) / 4


@pytest.mark.parametrize("n, c", [(6, 4), (9, 9), (7, 1), (12, 10)])
def test_schur_solve_equals_ldl_solve_on_random_spd_matrices(n, c):
    rng = np.random.default_rng(n + c)
    A = rng.normal(size=(n, n))
    M = A @ A.T + n * np.eye(n)
    b = rng.normal(size=n)
    block = np.sort(rng.choice(n, size=c, replace=False)).astype(np.int64)
    rest = np.array([i for i in range(n) if i not in block], dtype=np.int64)
    p = np.full(3 + 2 + c * c, -1.0)
    constant_block_factor.py_func(M[np.ix_(block, block)].copy(), p, 3)
    assert p[3] == 0.0
    upper = np.triu(M)
    upper[np.ix_(block, block)] = np.nan   # the block is never read
    x = b.copy()
    assert schur_solve.py_func(upper, x, p, 3, block, rest) == 0
    x_ldl = b.copy()
    assert ldl_solve.py_func(np.triu(M), x_ldl) == 0
    np.testing.assert_allclose(x, x_ldl, rtol=1e-12, atol=1e-14)
    np.testing.assert_allclose(M @ x, b, rtol=1e-12, atol=1e-12)


def test_schur_solve_flags_a_singular_block_or_complement_as_ldl_solve_does():
    block, rest = np.array([1, 2], dtype=np.int64), np.array([0], dtype=np.int64)
    M = np.array([[2.0, 0.1, 0.2], [0.0, 1.0, 1.0], [0.0, 0.0, 1.0]])   # upper triangle
    for G, code in (([[1.0, 1.0], [1.0, 1.0]], 4), ([[0.0, 0.0], [0.0, 0.0]], 4),
                    ([[-1.0, 0.0], [0.0, 1.0]], 4), ([[np.nan, 0.0], [0.0, 1.0]], 2)):
        p = np.empty(2 + 4)
        constant_block_factor.py_func(np.array(G), p, 0)
        b = np.ones(3)
        assert schur_solve.py_func(M, b, p, 0, block, rest) == code
        assert np.all(np.isnan(b))
    p = np.empty(2 + 4)
    constant_block_factor.py_func(np.eye(2), p, 0)
    singular_rest = np.array([[1.0, 1.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])   # S = 0
    b = np.ones(3)
    assert schur_solve.py_func(singular_rest, b, p, 0, block, rest) == 4
    assert np.all(np.isnan(b))


def test_generated_block_solve_agrees_with_plain_ldl_solve(arm, arm_modules):
    assert "schur_solve(_M" in generate_rhs_source(arm)
    assert "rhs_part1(" in arm_modules.parts_source and "schur_solve(_M" in arm_modules.parts_source
    rng = np.random.default_rng(7)
    p = modal_arm_constants(arm, rng)
    exact = lambdified_solution(arm)
    prepared = prepared_parameters(arm_modules.block, p)
    assert prepared.shape == (arm_modules.block.NP_PREPARED,) and np.array_equal(prepared[:p.size], p)
    assert prepared_parameters(arm_modules.block, prepared) is prepared
    for time in (0.0, 0.4, 1.3):
        y = rng.normal(scale=0.5, size=24)
        dy = {}
        for label, module, params in (("block", arm_modules.block, prepared),
                                      ("unprepared", arm_modules.block, p),
                                      ("parts", arm_modules.parts, prepared_parameters(arm_modules.parts, p)),
                                      ("plain", arm_modules.plain, p)):
            dy[label] = np.empty(24)
            assert module.rhs(time, y, params, dy[label]) == 0
        scale = np.max(np.abs(dy["plain"][12:]))
        np.testing.assert_array_equal(dy["block"], dy["unprepared"])
        np.testing.assert_array_equal(dy["block"][:12], y[12:])
        for label in ("block", "parts"):
            np.testing.assert_allclose(dy[label], dy["plain"], rtol=0, atol=1e-14 * scale)
        np.testing.assert_allclose(dy["block"][12:], exact(time, y, p), rtol=1e-11, atol=1e-13 * scale)


def test_state_dependent_modal_block_keeps_the_plain_solve(models):
    stiffened = modal_arm(stiffening=True)
    source = generate_rhs_source(stiffened)
    assert "schur_solve" not in source and "ldl_solve(_M" in source and "rhs_prepare" not in source
    module = models.compile(stiffened)
    rng = np.random.default_rng(3)
    p = modal_arm_constants(stiffened, rng)
    assert prepared_parameters(module, p).shape == p.shape
    y = rng.normal(scale=0.5, size=24)
    dy = np.empty(24)
    assert module.rhs(0.2, y, prepared_parameters(module, p), dy) == 0
    np.testing.assert_allclose(dy[12:], lambdified_solution(stiffened)(0.2, y, p), rtol=1e-11, atol=1e-12)


def test_singular_modal_block_is_status_4_not_a_traceback(arm, arm_modules):
    p = modal_arm_constants(arm, np.random.default_rng(2), modal_mass_scale=0.0)  # G = 0
    dy = np.empty(24)
    assert arm_modules.block.rhs(0.0, np.zeros(24), prepared_parameters(arm_modules.block, p), dy) == 4
    assert np.all(np.isnan(dy[12:]))
    result = integrate(arm_modules.block, np.zeros(24), np.linspace(0.0, 0.1, 3), p, rtol=1e-8,
                       atol=1e-10, method="dop853")
    assert result.status == Status.SINGULAR_MASS_MATRIX and result.t_reached == 0.0
    assert "singular mass matrix" in result.message
    bad = modal_arm_constants(arm, np.random.default_rng(2))
    bad[[k for k, s in enumerate(arm.constants) if s.name == "G_1_1"]] = np.nan
    assert arm_modules.block.rhs(0.0, np.zeros(24), prepared_parameters(arm_modules.block, bad), dy) == 2


def test_integrate_prepares_the_constants_once_per_run(arm, arm_modules, monkeypatch):
    integrate_module = importlib.import_module("flexkane.numerics.integrate")
    calls = []

    def spy(module, p, name="rhs"):
        calls.append(np.asarray(p).shape)
        return prepared_parameters(module, p, name)

    monkeypatch.setattr(integrate_module, "prepared_parameters", spy)
    p = modal_arm_constants(arm, np.random.default_rng(5))
    y0 = np.r_[0.3, -0.2, np.full(10, 0.01), np.zeros(12)]
    result = integrate(arm_modules.block, y0, np.linspace(0.0, 0.5, 11), p, rtol=1e-9, atol=1e-11)
    assert result.success and calls == [p.shape]
    plain = integrate(arm_modules.plain, y0, np.linspace(0.0, 0.5, 11), p, rtol=1e-9, atol=1e-11,
                      method=result.method)
    # same equations, same method: the runs differ by the integration error, not more
    np.testing.assert_allclose(result.y, plain.y, rtol=0, atol=1e-7)
