"""The derived F*_r and elastic F_r equal eqs. 8.23 and 8.31 of the chapter, term by term."""

import pytest
import sympy as sp

from flexkane.builtin import builtin_model
from flexkane.kane import derive
from flexkane.model.values import GeneratedSymbol

#: Coordinates, speeds and modal constants are symbols flexkane generates; parameters are plain.
S = lambda name: GeneratedSymbol(name, real=True)  # noqa: E731
P = lambda name: sp.Symbol(name, real=True)  # noqa: E731


def _symbols(n):
    q = [S(f"q{k}") for k in range(1, 4 + n)]
    u = [S(f"u{k}") for k in range(1, 4 + n)]
    ud = [S(f"u{k}'") for k in range(1, 4 + n)]
    E = [S(f"E_{i}") for i in range(1, n + 1)]
    F = [S(f"F_{i}") for i in range(1, n + 1)]
    G = [[S(f"G_{min(i, j)}{max(i, j)}") for j in range(1, n + 1)] for i in range(1, n + 1)]
    H = [[S(f"H_{min(i, j)}{max(i, j)}") for j in range(1, n + 1)] for i in range(1, n + 1)]
    return q, u, ud, E, F, G, H, S


def chapter_F_star(n):
    """Eq. 8.23 typed from the chapter."""
    q, u, ud, E, F, G, H, S = _symbols(n)
    mR, Iz, b, mB, eB, IB = P("mR"), P("Iz"), P("b"), S("m_B"), S("e_B"), S("I_B")
    u1, u2, u3 = u[:3]
    d1, d2, d3 = ud[:3]
    qm, um, dm = q[3:], u[3:], ud[3:]
    sum_Eq = sum(E[i] * qm[i] for i in range(n))
    sum_Eu = sum(E[i] * um[i] for i in range(n))
    F1 = -(mR + mB) * (d1 - u2 * u3) + d3 * sum_Eq + 2 * u3 * sum_Eu + u3 ** 2 * (b * mB + eB)
    F2 = (-(mR + mB) * (d2 + u3 * u1) - sum(E[i] * dm[i] for i in range(n))
          - d3 * (b * mB + eB) + u3 ** 2 * sum_Eq)
    F3 = ((d1 - u2 * u3) * sum_Eq - (d2 + u3 * u1) * (b * mB + eB)
          - d3 * (b ** 2 * mB + 2 * b * eB + IB + Iz) - sum(dm[i] * (b * E[i] + F[i]) for i in range(n))
          - 2 * u3 * sum(G[i][k] * qm[i] * um[k] for i in range(n) for k in range(n))
          - d3 * sum(G[i][k] * qm[i] * qm[k] for i in range(n) for k in range(n)))
    Fj = [(-d2 * E[j] - sum(G[i][j] * dm[i] for i in range(n)) - d3 * (b * E[j] + F[j])
           - u3 * u1 * E[j] + u3 ** 2 * sum(G[i][j] * qm[i] for i in range(n))) for j in range(n)]
    return [F1, F2, F3] + Fj


def chapter_F_elastic(n):
    """Eq. 8.31."""
    q, u, ud, E, F, G, H, S = _symbols(n)
    return [0, 0, 0] + [-sum(H[i][j] * q[3 + i] for i in range(n)) for j in range(n)]


@pytest.mark.parametrize("n", [1, 2, 3])
def test_generalized_inertia_forces_equal_eq_8_23_term_by_term(n):
    eom = derive(builtin_model("falling-beam-exact").with_modes(n))
    assert [s.name for s in eom.all_speeds] == [f"u{k}" for k in range(1, 4 + n)]
    for derived, typed in zip(eom.F_r_star, chapter_F_star(n)):
        assert sp.expand(derived - typed) == 0


@pytest.mark.parametrize("n", [1, 2, 3])
def test_elastic_active_forces_equal_eq_8_31(n):
    eom = derive(builtin_model("falling-beam-exact").with_modes(n))
    for derived, typed in zip(eom.F_r["elastic"], chapter_F_elastic(n)):
        assert sp.expand(derived - typed) == 0


def test_gravity_forces_equal_eq_8_34_with_weight_at_the_deformed_midpoint():
    eom = derive(builtin_model("falling-beam"))
    mR, mB, g, b, q3, q4, u = P("mR"), S("m_B"), P("g"), P("b"), S("q3"), S("q4"), None
    L = P("L")
    phi_mid = S("Phi_1(L/2)")
    s3, c3 = sp.sin(q3), sp.cos(q3)
    # G_R = -mR g (s3 i + c3 j), G_B = -mB g (s3 i + c3 j) at C_B, eq. 8.33; partial velocities of
    # C_R and C_B (eq. 8.19) dotted with them, eq. 8.34
    GR = (-mR * g * s3, -mR * g * c3)
    GB = (-mB * g * s3, -mB * g * c3)
    expected = [GR[0] + GB[0], GR[1] + GB[1], GB[0] * (-phi_mid * q4) + GB[1] * (b + L / 2), GB[1] * phi_mid]
    for derived, typed in zip(eom.F_r["gravity"], expected):
        assert sp.simplify(derived - typed) == 0
