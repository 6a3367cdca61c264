"""Modal integrals of eqs. 8.22 and 8.32 by Gauss-Legendre quadrature."""

import numpy as np
import pytest
import sympy
from scipy.integrate import quad

from flexkane.errors import ModelError
from flexkane.modes import get_family
from flexkane.modes.integrals import (foreshortening, gauss_legendre, gram, mass_integrals,
                                      quadrature_order, stiffening_integrals, stiffness_integrals)

L, RHO, EI = 1.3, 0.21991, 35.3
M = RHO * L


def test_cantilever_modes_are_orthogonal_in_mass_eq_8_8():
    G = mass_integrals(get_family("clamped-free"), 30, L, RHO).G
    np.testing.assert_allclose(G / M, np.eye(30), atol=1e-10)


def test_cantilever_modes_are_orthogonal_in_stiffness_eq_8_9():
    family = get_family("clamped-free")
    H = stiffness_integrals(family, 30, L, EI)
    p = family.frequencies(30, L, EI, RHO)
    scale = np.sqrt(np.outer(np.diag(H), np.diag(H)))
    np.testing.assert_allclose(H / scale, np.eye(30), atol=1e-10)
    np.testing.assert_allclose(np.diag(H), M * p ** 2, rtol=1e-10)


@pytest.mark.parametrize("name", ["pinned-free", "pinned-pinned", "clamped-pinned",
                                  "clamped-clamped", "free-free"])
def test_other_eigenfunction_families_are_orthogonal(name):
    family = get_family(name)
    n = 30
    G = mass_integrals(family, n, L, RHO).G
    np.testing.assert_allclose(G / M, np.eye(n), atol=1e-10)
    H = stiffness_integrals(family, n, L, EI)
    p = family.frequencies(n, L, EI, RHO)
    np.testing.assert_allclose(H / np.sqrt(np.outer(np.diag(H), np.diag(H))), np.eye(n), atol=1e-10)
    np.testing.assert_allclose(np.diag(H), M * p ** 2, rtol=1e-10)


def test_cantilever_E_and_F_have_closed_forms():
    # Phi = Phi'''' / lambda^4 and the end conditions give
    # int_0^1 Phi dxi = -Phi'''(0) / lambda^4 = 2 sigma / lambda,
    # int_0^1 xi Phi dxi = Phi''(0) / lambda^4 = 2 / lambda^2
    family = get_family("clamped-free")
    n = 30
    lam = family.roots(n)
    sigma = (np.cosh(lam) + np.cos(lam)) / (np.sinh(lam) + np.sin(lam))
    integrals = mass_integrals(family, n, L, RHO)
    np.testing.assert_allclose(integrals.E, 2 * M * sigma / lam, rtol=1e-12)
    np.testing.assert_allclose(integrals.F, 2 * M * L / lam ** 2, rtol=1e-12)
    # and plain quadrature agrees, to rounding of an O(rho L) oscillating integrand
    modes = lambda x: family.phi(x / L, n)  # noqa: E731
    by_quadrature = gram(modes, lambda x: np.vstack([np.ones_like(x), x]), L, lambda x: RHO + 0 * x)
    np.testing.assert_allclose(by_quadrature[:, 0], 2 * M * sigma / lam, rtol=0, atol=1e-14 * M)
    np.testing.assert_allclose(by_quadrature[:, 1], 2 * M * L / lam ** 2, rtol=0, atol=1e-14 * M * L)


def test_rigid_body_constants_of_a_uniform_beam():
    integrals = mass_integrals(get_family("clamped-free"), 2, L, RHO)
    assert integrals.m_B == pytest.approx(M, rel=1e-15)
    assert integrals.e_B == pytest.approx(M * L / 2, rel=1e-15)
    assert integrals.I_B == pytest.approx(M * L ** 2 / 3, rel=1e-15)


def test_free_free_modes_have_no_net_momentum():
    integrals = mass_integrals(get_family("free-free"), 20, L, RHO)
    assert np.abs(integrals.E).max() < 1e-13 * M
    assert np.abs(integrals.F).max() < 1e-13 * M * L


def test_chosen_order_is_converged_for_mode_50():
    family = get_family("clamped-free")
    order = quadrature_order(family, 50)
    x, w = gauss_legendre(order)
    x2, w2 = gauss_legendre(2 * order)
    for k in (0, 1, 2):
        a, b = family.phi(x, 50, k), family.phi(x2, 50, k)
        g1, g2 = (a * w) @ a.T, (b * w2) @ b.T
        scale = np.sqrt(np.outer(np.diag(g2), np.diag(g2)))
        assert np.abs(g1 - g2).max() < 1e-12 * scale.max()
    np.testing.assert_allclose(mass_integrals(family, 50, L, RHO).G / M, np.eye(50), atol=1e-11)


def test_tip_mass_family_is_orthogonal_only_with_the_tip_body():
    mu, kappa = 0.8, 0.05
    family = get_family("clamped-free-tip-mass", mass_ratio=mu, inertia_ratio=kappa)
    n = 10
    G = mass_integrals(family, n, L, RHO).G
    tip, slope = family.phi(1.0, n)[:, 0], family.phi(1.0, n, 1)[:, 0] / L
    total = G + mu * M * np.outer(tip, tip) + kappa * RHO * L ** 3 * np.outer(slope, slope)
    np.testing.assert_allclose(total / M, np.eye(n), atol=1e-12)
    assert np.abs(G / M - np.eye(n)).max() > 1e-2


def test_axial_stiffness_integrals_use_first_derivatives():
    family = get_family("axial-fixed-free")
    EA = 2.0e6
    beta = family.roots(5)
    np.testing.assert_allclose(stiffness_integrals(family, 5, L, EA), np.diag(EA * beta ** 2 / L),
                               rtol=1e-12, atol=1e-9 * EA)


def test_polynomial_integrals_are_exact():
    family = get_family("polynomial")
    n = 4
    integrals = mass_integrals(family, n, L, RHO)
    k = np.arange(1, n + 1)
    np.testing.assert_allclose(integrals.E, M / (k + 2), rtol=1e-14)
    np.testing.assert_allclose(integrals.F, M * L / (k + 3), rtol=1e-14)
    np.testing.assert_allclose(integrals.G, M / (k[:, None] + k[None, :] + 3), rtol=1e-14)
    H = stiffness_integrals(family, n, L, EI)
    a, b = k[:, None] + 1, k[None, :] + 1
    np.testing.assert_allclose(H, EI / L ** 3 * a * (a - 1) * b * (b - 1) / (a + b - 3), rtol=1e-13)


def test_results_are_cached_but_callers_get_their_own_arrays():
    family = get_family("clamped-free")
    first = mass_integrals(family, 6, L, RHO)
    first.G[0, 0] = -1.0
    again = mass_integrals(get_family("clamped-free"), 6, L, RHO)
    assert again.G[0, 0] == pytest.approx(M)


def test_gram_integrates_products_with_a_weight():
    funcs = lambda x: np.vstack([np.ones_like(x), x, np.sin(x)])  # noqa: E731
    weight = lambda x: 2.0 + x  # noqa: E731
    result = gram(funcs, funcs, 2.0, weight)
    expected = np.empty((3, 3))
    f = [lambda x: 1.0, lambda x: x, np.sin]
    for i in range(3):
        for j in range(3):
            expected[i, j] = quad(lambda x: (2 + x) * f[i](x) * f[j](x), 0, 2, epsabs=1e-15)[0]
    np.testing.assert_allclose(result, expected, rtol=1e-13)


def test_foreshortening_of_polynomials_has_a_closed_form():
    family = get_family("polynomial")
    x = np.array([0.0, 0.3, 1.1, L])
    d = foreshortening(family, 3, L, x)
    i = np.arange(1, 4)[:, None, None]
    j = np.arange(1, 4)[None, :, None]
    expected = (i + 1) * (j + 1) * (x / L) ** (i + j + 1) / ((i + j + 1) * L)
    np.testing.assert_allclose(d, expected, rtol=1e-13, atol=1e-16)


def test_foreshortening_of_cantilever_modes_matches_adaptive_quadrature():
    family = get_family("clamped-free")
    n = 50
    x = np.array([0.37 * L, L])
    d = foreshortening(family, n, L, x)
    for i, j in ((0, 0), (3, 7), (49, 49), (10, 49)):
        slope = lambda s, k: family.phi(s / L, n, 1)[k, 0] / L  # noqa: E731
        for p, xp in enumerate(x):
            ref = quad(lambda s: slope(s, i) * slope(s, j), 0, xp, limit=500, epsabs=1e-13)[0]
            scale = np.sqrt(d[i, i, -1] * d[j, j, -1])
            assert abs(d[i, j, p] - ref) < 1e-11 * scale
    np.testing.assert_allclose(d, d.transpose(1, 0, 2), rtol=0, atol=0)


def test_stiffening_with_unit_weight_is_the_full_length_foreshortening():
    family = get_family("clamped-free")
    d = foreshortening(family, 8, L, np.array([L]))[:, :, 0]
    s = stiffening_integrals(family, 8, L, lambda x: np.ones_like(x))
    np.testing.assert_allclose(s, d, rtol=1e-12, atol=1e-12 * np.abs(d).max())


def test_centrifugal_stiffening_integrals_match_adaptive_quadrature():
    family = get_family("clamped-free")
    omega = 3.0
    tension = lambda x: RHO * omega ** 2 * (L ** 2 - x ** 2) / 2  # noqa: E731
    s = stiffening_integrals(family, 6, L, tension)
    for i, j in ((0, 0), (1, 4), (5, 5)):
        def f(x):
            slope = family.phi(x / L, 6, 1)[:, 0] / L
            return tension(x) * slope[i] * slope[j]
        ref = quad(f, 0, L, epsabs=1e-14, limit=200)[0]
        assert s[i, j] == pytest.approx(ref, rel=1e-11, abs=1e-13)


def test_singular_shape_functions_are_reported_instead_of_integrated_wrongly():
    xi = sympy.Symbol("xi")
    family = get_family("expression", expressions=[xi ** sympy.Rational(3, 2)])
    with pytest.raises(ModelError, match="converge"):
        stiffness_integrals(family, 1, L, EI)


@pytest.mark.parametrize("call, path", [
    (lambda f: mass_integrals(f, 3, -1.0, RHO), "L"),
    (lambda f: mass_integrals(f, 3, L, 0.0), "rho"),
    (lambda f: stiffness_integrals(f, 3, L, float("inf")), "EI"),
    (lambda f: foreshortening(f, 3, L, [2 * L]), "x"),
])
def test_bad_physical_arguments_are_model_errors(call, path):
    with pytest.raises(ModelError) as info:
        call(get_family("clamped-free"))
    assert info.value.path == path
