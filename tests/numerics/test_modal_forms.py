"""Linear forms of the state taken out of the term tables (a beam's modal sums G q, H q) give the
numbers of the written-out code, and each form is evaluated once however many sums read it."""

from __future__ import annotations

import math
import types

import numpy as np
import pytest
import sympy as sp

from flexkane.numerics import generate_rhs_source, large_rhs
from flexkane.numerics.constant_block import prepared_parameters
from flexkane.numerics.large_rhs import FORM_TERMS_MIN, modal_forms
from flexkane.numerics.linear_algebra import constant_block_factor, schur_solve

N_MODES = 12


def spinning_beam(n=N_MODES):
    """A hub (angle x, rate u) carrying a beam's modes e (rates v), with the beam's modal sums.

    ``M = [[J + e^T G e, F^T], [F, G]]``, ``f_0 = -2 u e^T G v - g sin x`` and
    ``f_i = u^2 (G e)_i - (H e)_i``: a symmetric quadratic form, a bilinear form and two
    matrix-vector products, every sum of n or n^2 terms (the structure of eqs. 8.22 and 8.31).
    """
    t, x, u, J, g = sp.symbols("t x u J g")
    e = sp.symbols(f"e1:{n + 1}")
    v = sp.symbols(f"v1:{n + 1}")
    F = sp.symbols(f"F1:{n + 1}")
    G = sp.Matrix(n, n, lambda i, j: sp.Symbol(f"G_{min(i, j) + 1}_{max(i, j) + 1}"))
    H = sp.Matrix(n, n, lambda i, j: sp.Symbol(f"H_{min(i, j) + 1}_{max(i, j) + 1}"))
    ev, vv = sp.Matrix(e), sp.Matrix(v)
    M = sp.zeros(n + 1, n + 1)
    M[0, 0] = J + sp.expand((ev.T * G * ev)[0])
    for i in range(n):
        M[0, i + 1] = M[i + 1, 0] = F[i]
        for j in range(n):
            M[i + 1, j + 1] = G[i, j]
    forcing = [sp.expand(-2 * u * (ev.T * G * vv)[0]) - g * sp.sin(x)]
    forcing += [sp.expand(u ** 2 * (G * ev)[i] - (H * ev)[i]) for i in range(n)]
    constants = sorted((M.free_symbols | sp.Matrix(forcing).free_symbols) - {x, u, t} - set(e) - set(v),
                       key=lambda s: s.name)
    return types.SimpleNamespace(t=t, q=[x, *e], u=[u, *v], constants=constants, qdot=sp.Matrix([u, *v]),
                                 mass_matrix=M, forcing=sp.Matrix(forcing))


def spinning_beam_constants(eom, rng):
    n = sum(1 for s in eom.constants if s.name.startswith("F"))
    A = rng.normal(size=(n, n))
    B = rng.normal(size=(n, n))
    matrices = {"G": A @ A.T / n + np.eye(n), "H": B @ B.T + n * np.eye(n)}
    values = []
    for s in eom.constants:
        if s.name[0] in "GH":
            i, j = (int(k) - 1 for k in s.name[2:].split("_"))
            values.append(matrices[s.name[0]][i, j])
        else:
            values.append({"J": 4.0, "g": 9.81}.get(s.name, rng.uniform(-0.2, 0.2)))
    return np.array(values)


@pytest.fixture(scope="module")
def beam_modules(models):
    eom = spinning_beam()
    mp = pytest.MonkeyPatch()
    mp.setattr(large_rhs, "SPLIT_CHARS", 300)
    source = generate_rhs_source(eom)
    forms = models.compile(eom)
    mp.undo()
    mp.setattr(large_rhs, "SPLIT_CHARS", 10 ** 9)
    plain = models.compile(eom)
    mp.undo()
    return types.SimpleNamespace(eom=eom, source=source, forms=forms, plain=plain)


def test_forms_agree_with_straight_line_code_at_random_states(beam_modules):
    m = beam_modules
    assert "def rhs_table_forms(" in m.source and "rhs_table_forms(w, p, " in m.source
    assert "rhs_table_forms" not in open(m.plain.__file__).read()
    rng = np.random.default_rng(16)
    p = spinning_beam_constants(m.eom, rng)
    prepared = prepared_parameters(m.forms, p)
    n = 2 * (N_MODES + 1)
    for time in (0.0, 0.4, 1.3):
        for scale in (1e-3, 0.3, 2.0):
            y = rng.normal(scale=scale, size=n)
            a, b = np.empty(n), np.empty(n)
            assert m.forms.rhs(time, y, prepared, a) == 0 and m.plain.rhs(time, y, p, b) == 0
            np.testing.assert_allclose(a, b, rtol=1e-12, atol=1e-12 * np.max(np.abs(b)))


def test_each_modal_sum_is_one_form_shared_by_every_sum_that_reads_it(beam_modules):
    # e^T G e, e^T G v and u^2 G e all read G e (the quadratic form by its symmetric rows, the
    # bilinear one with the factor 2 kept in its term): the forms are G e and H e, n rows each, in
    # one matrix over the modal coordinates e = y[1:n + 1]
    blocks = beam_modules.forms.RHS_FORMS_TABLE_INDEX
    assert blocks.tolist() == [[1, N_MODES + 1, blocks[0, 2], 2 * N_MODES, blocks[0, 4]]]


def _evaluate(groups, forms, values, constants):
    """The sums of ``groups`` (Python floats) with ``forms`` evaluated from ``values``."""
    def coefficient(contributions):
        return sum(c * math.prod(constants[f] for f in fixed) for c, fixed in contributions)

    values = dict(values)
    state = list(values)
    for (lo, hi, first, rows), entries in zip(forms.blocks, forms.entries):
        for r in range(rows):
            values[forms.names[first + r]] = sum(coefficient(entries[(j - lo) * rows + r]) * values[state[j]]
                                                 for j in range(lo, hi))
    return [sum(coefficient(c) * math.prod(values[f] for f in factors) for factors, c in g.items())
            for g in groups]


def test_modal_forms_rewrite_sums_into_forms_with_the_same_value():
    # sums as the tables hold them: J = sum_ij G_ij q_i q_j (i <= j, 2 G_ij off the diagonal),
    # K = sum_ij 2 G_ij q_i u_j w, f_i = w^2 sum_j G_ij q_j, and a sum too short for a form
    n = FORM_TERMS_MIN + 2
    q = [f"q{i}" for i in range(n)]
    u = [f"u{i}" for i in range(n)]

    def G(i, j):
        return f"G_{min(i, j)}_{max(i, j)}"

    J = {tuple(sorted((q[i], q[j]))): [(1.0 if i == j else 2.0, (G(i, j),))]
         for i in range(n) for j in range(i, n)}
    K = {tuple(sorted((q[i], u[j], "w"))): [(2.0, (G(i, j),))] for i in range(n) for j in range(n)}
    f = [{tuple(sorted((q[j], "w", "w"))): [(1.0, (G(i, j),))] for j in range(n)} for i in range(n)]
    short = {(q[0], u[1]): [(3.0, ())], ("w",): [(-1.0, ("c",))]}
    groups = [J, K, *f, short]
    rewritten, forms = modal_forms(groups, [*q, *u])
    assert len(forms.names) == n and len(forms.blocks) == 1        # G q only
    assert forms.blocks[0][:2] == (0, n)
    assert [len(g) for g in rewritten] == [n, n] + [1] * n + [2]
    assert rewritten[-1] == short
    rng = np.random.default_rng(3)
    A = rng.normal(size=(n, n))
    Gm = A + A.T
    constants = {G(i, j): Gm[i, j] for i in range(n) for j in range(n)} | {"c": 0.7}
    values = {name: rng.normal() for name in [*q, *u]} | {"w": 1.3}
    expected = _evaluate(groups, large_rhs.ModalForms([], [], []), values, constants)
    np.testing.assert_allclose(_evaluate(rewritten, forms, values, constants), expected, rtol=1e-12)


def test_modal_forms_leave_sums_without_shared_forms_alone():
    # f_i = sum_j -K_ij x_j^2 u_j: every term has its own factors; no form
    n = 12
    groups = [{tuple(sorted((f"x{j}", f"x{j}", f"u{j}"))): [(-1.0, (f"K_{i}_{j}",))] for j in range(n)}
              for i in range(n)]
    rewritten, forms = modal_forms(groups, [*(f"x{j}" for j in range(n)), *(f"u{j}" for j in range(n))])
    assert rewritten == groups and forms.names == []


def _row_by_row_schur_solve(M, b, p, offset, block, rest):
    """The block solve with row-by-row forward substitutions (the order of the dot products)."""
    c = block.shape[0]
    f0 = offset + 2
    L = np.array([[p[f0 + i * c + k] if k < i else 0.0 for k in range(c)] for i in range(c)])
    inv_d = np.array([p[f0 + k * c + k] for k in range(c)])
    z = np.empty(c)
    for k in range(c):
        s = b[block[k]]
        for j in range(k):
            s -= L[k, j] * z[j]
        z[k] = s
    (ra,) = rest
    y = np.empty(c)
    for k in range(c):
        s = M[block[k], ra] if block[k] < ra else M[ra, block[k]]
        for j in range(k):
            s -= L[k, j] * y[j]
        y[k] = s
    yd = y * inv_d
    g = b[ra]
    for k in range(c):
        g -= yd[k] * z[k]
    S = M[ra, ra]
    for k in range(c):
        S -= yd[k] * y[k]
    x_r = g / S
    for k in range(c):
        z[k] = (z[k] - y[k] * x_r) * inv_d[k]
    for k in range(c - 1, -1, -1):
        for j in range(k):
            z[j] -= L[k, j] * z[k]
    x = np.empty_like(b)
    x[block] = z
    x[ra] = x_r
    return x


def test_schur_solve_by_columns_of_l_gives_the_bits_of_row_by_row_substitution():
    # 42 modal speeds and one rest (falling-beam-exact, 40 modes): the substitutions run over the
    # columns of L (vectorized), each entry's operations in the order of the row-by-row version
    rng = np.random.default_rng(40)
    n = 43
    A = rng.normal(size=(n, n))
    M = A @ A.T + n * np.eye(n)
    b = rng.normal(size=n)
    block = np.array([i for i in range(n) if i != 2], dtype=np.int64)
    rest = np.array([2], dtype=np.int64)
    p = np.zeros(2 + (n - 1) ** 2)
    constant_block_factor(M[np.ix_(block, block)].copy(), p, 0)
    x = b.copy()
    assert schur_solve(np.triu(M), x, p, 0, block, rest) == 0
    np.testing.assert_array_equal(x, _row_by_row_schur_solve(np.triu(M), b, p, 0, block, rest))
    np.testing.assert_allclose(M @ x, b, rtol=1e-12, atol=1e-12)


@pytest.mark.slow
def test_falling_beam_exact_with_40_modes_has_g_q_and_h_q_as_forms_and_the_same_numbers(models, monkeypatch):
    import flexkane

    model = flexkane.builtin_model("falling-beam-exact").with_modes(40)
    eom = flexkane.derive(model)
    forms = models.compile(eom)
    with monkeypatch.context() as mp:
        mp.setattr(large_rhs, "FORM_TERMS_MIN", 10 ** 9)
        plain = models.compile(eom)
    assert not hasattr(plain, "RHS_FORMS_TABLE_INDEX")
    # the modal coordinates are y[3:43]: G q and H q (40 rows each) and E . q in one matrix
    lo, hi, _, rows, _ = forms.RHS_FORMS_TABLE_INDEX[0]
    assert (lo, hi, rows) == (3, 43, 81)
    values = eom.constant_values(model)
    p = np.array([values[s] for s in eom.constants], dtype=float)
    y0 = np.asarray(eom.initial_state(model), dtype=float)
    rng = np.random.default_rng(40)
    for _ in range(10):
        y = y0 + rng.normal(scale=0.05, size=y0.shape[0])
        a, b = np.empty_like(y), np.empty_like(y)
        assert forms.rhs(0.2, y, prepared_parameters(forms, p), a) == 0
        assert plain.rhs(0.2, y, prepared_parameters(plain, p), b) == 0
        np.testing.assert_allclose(a, b, rtol=1e-12, atol=1e-12 * np.max(np.abs(b)))


def test_operation_count_of_the_work_model_is_that_of_the_tables_and_forms(beam_modules):
    """``RHS_OPERATIONS`` (the integrators' work per evaluation) counts what one call computes: with
    the forms, each matrix entry once (a product and a sum) and each remaining term of d factors
    (d products and a sum), not the written-out sums that the tables replace."""
    forms, plain = beam_modules.forms, beam_modules.plain
    blocks = forms.RHS_FORMS_TABLE_INDEX
    entries = int(((blocks[:, 1] - blocks[:, 0]) * blocks[:, 3]).sum())
    factors = [getattr(forms, f"RHS_D{d}_TABLE_INDEX") for d in range(1, 8)
               if hasattr(forms, f"RHS_D{d}_TABLE_INDEX")]
    terms = sum(table.size + table.shape[0] for table in factors)   # d products and a sum each
    assert entries == 2 * N_MODES * N_MODES
    assert forms.RHS_OPERATIONS >= 2 * entries + terms
    # the sums as written out: every term of u^2 G e, H e, e^T G e, e^T G v multiplies its factors
    assert forms.RHS_OPERATIONS < 0.8 * plain.RHS_OPERATIONS
