"""Modal sums (flexkane.kane.modal_sums): a beam's integrals kept as indexed sums over its modal
constants, equal to the equations written out term by term, printed in indexed form and evaluated by
loops in the generated code."""

import numpy as np
import pytest
import sympy as sp

import flexkane.kane.modal_sums as modal_sums
from flexkane.kane.equations import derive
from flexkane.kane.modal_sums import ModalSum, modal_sum, written_out_sums
from flexkane.model import loads_model
from flexkane.numerics import modal_loops
from flexkane.numerics.codegen import generate_rhs_source
from flexkane.report import equations_markdown

q = sp.symbols("q1:4")
u = sp.symbols("u1:4")
w = sp.Symbol("w")
G = sp.symbols("G1:10")
E = sp.symbols("E1:4")


@pytest.fixture
def every_sum(monkeypatch):
    """Modal sums of any length (short ones are written out by default)."""
    monkeypatch.setattr(modal_sums, "MODAL_SUM_MIN_TERMS", 1)


def test_a_short_modal_sum_is_written_out():
    assert modal_sum("E_y", E, (3,), q) == E[0] * q[0] + E[1] * q[1] + E[2] * q[2]
    assert isinstance(modal_sum("G_y", [*G, *G[:3]], (3, 4), q, [*u, w]), ModalSum)


def test_derivative_of_a_modal_sum_is_the_derivative_of_its_terms(every_sum):
    s = modal_sum("G_y", G, (3, 3), [w * x for x in q], q)
    for x in (*q, w):
        assert sp.expand(written_out_sums(sp.diff(s, x)) - sp.diff(s.written_out(), x)) == 0


def test_a_modal_sum_of_numbers_is_a_number(every_sum):
    s = modal_sum("E_y", E, (3,), q)
    assert s.xreplace({**dict(zip(q, (1, 2, 3))), **dict(zip(E, (1.0, 0.5, 2.0)))}) == 8.0
    assert float(s.xreplace(dict(zip(q, (1, 2, 3)))).xreplace(dict(zip(E, (1, 1, 1))))) == 6.0
    assert s.subs(dict(zip(E, (1, 1, 1)))).evalf(subs=dict(zip(q, (1, 2, 3)))) == 6.0


def test_a_vector_of_one_term_picks_a_row_and_a_zero_vector_gives_zero(every_sum):
    assert modal_sum("G_y", G, (3, 3), [0, w, 0], q) == w * modal_sum("G_y", G[3:6], (3,), q)
    assert modal_sum("E_y", E, (3,), [0, 0, u[2]]) == E[2] * u[2]
    assert modal_sum("E_y", E, (3,), [0, 0, 0]) == 0


def test_a_modal_sum_prints_in_the_chapters_indexed_form(every_sum):
    s = modal_sum("G_y", G, (3, 3), q, u)
    assert str(s) == "Sum_ij(G_y_ij [q1, q2, q3]_i [u1, u2, u3]_j)"
    assert sp.latex(s).startswith(r"\sum_{i,j} G_{y,ij}")


def test_a_modal_sum_in_a_product_is_printed_in_parentheses_by_every_printer(every_sum):
    s = modal_sum("E_y", E, (3,), q)
    values = {**dict(zip(q, (0.5, -0.25, 2.0))), **dict(zip(E, (1.0, 3.0, -2.0))), w: 3.0}
    expected = float((w * s.written_out() - 1).xreplace(values))
    assert sp.lambdify([*q, *E, w], w * s - 1)(*values.values()) == pytest.approx(expected, rel=1e-15)
    assert str(w * s) == "w*(Sum_i(E_y_i [q1, q2, q3]_i))"
    assert sp.ccode(w * s).startswith("w*(")


def test_the_loops_of_the_generated_code_equal_the_sums():
    rng = np.random.default_rng(3)
    A, a, b = rng.normal(size=(4, 5)), rng.normal(size=4), rng.normal(size=5)
    assert modal_loops.modal_sum2.py_func(tuple(A.ravel()), tuple(a), tuple(b)) == pytest.approx(a @ A @ b, rel=1e-14)
    assert modal_loops.modal_sum1.py_func(tuple(A[0]), tuple(b)) == pytest.approx(A[0] @ b, rel=1e-14)


BLADE = """
dimensions = 3
name = "modal-sums"
[beams.b]
L = 1.7
rho = 2.5
EI_y = 900.0
EI_z = 1500.0
GJ = 300.0
rho_Ip = 0.008
rho_Iz = 0.003
n_modes_y = 4
n_modes_z = 4
n_torsion = 2
[bodies.tip]
mass = 0.5
inertia = [0.01, 0.02, 0.03]
[joints.hub]
type = "revolute"
parent = "ground"
child = "b"
axis = [0, 1, 1]
[joints.j2]
type = "weld"
parent = "b"
station = 1.7
child = "tip"
[gravity]
g = 9.81
direction = [0, 0, -1]
"""


def _at_a_state(eom, seed=1):
    """M (n, n) and f (n,) at a random state, every modal sum written out."""
    rng = np.random.default_rng(seed)
    values = {**eom.constant_values(), **{s: 0.1 * rng.normal() for s in [*eom.q, *eom.u]}, eom.t: 0.3}
    number = lambda e: float(written_out_sums(e).xreplace(values))  # noqa: E731
    return (np.array([[number(e) for e in row] for row in eom.mass_matrix.tolist()]),
            np.array([number(e) for e in eom.forcing]))


def test_equations_with_modal_sums_equal_the_equations_written_out(monkeypatch):
    model = loads_model(BLADE)
    indexed = derive(model)
    assert any(e.atoms(ModalSum) for e in indexed.compact.expressions())
    monkeypatch.setattr(modal_sums, "MODAL_SUM_MIN_ATOMS", 10 ** 9)
    written = derive(model)
    assert not any(e.atoms(ModalSum) for e in written.compact.expressions())
    (M1, f1), (M2, f2) = _at_a_state(indexed), _at_a_state(written)
    np.testing.assert_allclose(M1, M2, rtol=0, atol=1e-13 * abs(M2).max())
    np.testing.assert_allclose(f1, f2, rtol=0, atol=1e-13 * abs(f2).max())


def test_generated_code_evaluates_modal_sums_by_loops():
    source = generate_rhs_source(derive(loads_model(BLADE)))
    assert "modal_sum2((G_y1_y1, G_y1_y2, G_y1_y3, G_y1_y4, G_y1_y2, G_y2_y2" in source
    assert "modal_sum1((H_y" not in source   # the rows of H q, 4 terms each: written out


@pytest.mark.slow
def test_the_report_prints_modal_sums_in_indexed_form():
    assert r"\sum_{i,j} G_{y,y,ij}" in equations_markdown(derive(loads_model(BLADE)))


@pytest.mark.slow
def test_compiled_right_hand_side_with_loops_equals_the_one_written_out(monkeypatch, tmp_path):
    from flexkane.numerics.constant_block import prepared_parameters
    from flexkane.simulation import compile_model

    model = loads_model(BLADE)
    rates = []
    for k, threshold in enumerate((modal_sums.MODAL_SUM_MIN_ATOMS, 10 ** 9)):
        monkeypatch.setattr(modal_sums, "MODAL_SUM_MIN_ATOMS", threshold)
        eom = derive(model)
        module = compile_model(eom, cache_dir=tmp_path / str(k)).module
        y = eom.initial_state() + 0.05 * np.random.default_rng(0).normal(size=len(eom.q) + len(eom.u))
        dy = np.empty(len(y))
        assert module.rhs(0.1, y, prepared_parameters(module, eom.parameter_vector()), dy) == 0
        rates.append(dy)
    np.testing.assert_allclose(rates[0], rates[1], rtol=0, atol=1e-12 * abs(rates[1]).max())
