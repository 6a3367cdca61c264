"""Term tables with their constant factors multiplied out once per run give the written-out numbers."""

from __future__ import annotations

import numpy as np
import pytest

from flexkane.numerics import generate_rhs_source, large_rhs
from flexkane.numerics.constant_block import prepared_parameters

from test_constant_block import modal_arm, modal_arm_constants
from test_large_rhs import coupled_masses


def _tables_and_straight_line(models, eom, monkeypatch):
    """The module of ``eom`` with term tables (split forced) and written out as one function."""
    with monkeypatch.context() as mp:
        mp.setattr(large_rhs, "SPLIT_CHARS", 300)
        source = generate_rhs_source(eom)
        tables = models.compile(eom)
    with monkeypatch.context() as mp:
        mp.setattr(large_rhs, "SPLIT_CHARS", 10 ** 9)
        plain = models.compile(eom)
    return source, tables, plain


@pytest.mark.parametrize("stiffening", [False, True], ids=["constant block", "no constant block"])
def test_tables_with_prepared_coefficients_equal_straight_line_code(models, monkeypatch, stiffening):
    # 14 modes: sums of 15 terms (u_1^2 sum_j G_ij e_j, J_a + sum_j e_j^2) become tables
    eom = modal_arm(n_modes=14, stiffening=stiffening)
    source, tables, plain = _tables_and_straight_line(models, eom, monkeypatch)
    assert "rhs_table_sums(w, p, " in source and "def rhs_table_coefficients(" in source
    assert "def rhs_prepare(" in source and ("schur_solve(_M" in source) != stiffening
    rng = np.random.default_rng(11)
    p = modal_arm_constants(eom, rng)
    prepared = prepared_parameters(tables, p)
    assert prepared.shape == (tables.NP_PREPARED,) and np.array_equal(prepared[:p.size], p)
    assert prepared_parameters(tables, prepared) is prepared
    n = 2 * (2 + 14)
    for time in (0.0, 0.9):
        y = rng.normal(scale=0.5, size=n)
        dy_tables, dy_raw, dy_plain = np.empty(n), np.empty(n), np.empty(n)
        assert tables.rhs(time, y, prepared, dy_tables) == 0
        assert tables.rhs(time, y, p, dy_raw) == 0          # raw constants: prepared on the call
        assert plain.rhs(time, y, p, dy_plain) == 0
        np.testing.assert_array_equal(dy_tables, dy_raw)
        scale = np.max(np.abs(dy_plain))
        np.testing.assert_allclose(dy_tables, dy_plain, rtol=1e-13, atol=1e-14 * scale)


def test_terms_are_stored_by_their_number_of_state_factors_with_constants_folded(models, monkeypatch):
    # f_i = sum_j (-K_ij x_j - D_ij u_j x_j^2) + a t sin(x_i): K_ij and D_ij go into the
    # coefficients, leaving terms of one factor (x_j) and of three (u_j, x_j, x_j); the work array
    # w holds the state, 1, t, 0, the sums and subexpressions, not the constants
    t, x, u, constants, mass, forcing = coupled_masses(n=12)
    eom = models.eom(t, x, u, constants, u, mass, forcing)
    source, tables, plain = _tables_and_straight_line(models, eom, monkeypatch)
    assert "schur_solve" not in source and "def rhs_prepare(" in source
    for d in (1, 3):
        index = getattr(tables, f"RHS_D{d}_TABLE_INDEX")
        assert index.shape[1] == d and np.all(index != 24)     # w[24] = 1.0: no padding factor
    assert tables.NP_PREPARED == len(constants) + tables.RHS_TERMS_TABLE_INDEX.size - 1
    rng = np.random.default_rng(5)
    p = rng.uniform(0.5, 1.5, len(constants))
    y = rng.normal(scale=0.3, size=24)
    dy_tables, dy_plain = np.empty(24), np.empty(24)
    assert tables.rhs(0.4, y, p, dy_tables) == 0 and plain.rhs(0.4, y, p, dy_plain) == 0
    np.testing.assert_allclose(dy_tables, dy_plain, rtol=1e-13, atol=1e-14 * np.max(np.abs(dy_plain)))
