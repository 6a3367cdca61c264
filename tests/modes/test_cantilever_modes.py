"""The chapter's cantilever (eqs. 8.2, 8.4, 8.6): end conditions, values, stability, typed roots."""

import numpy as np
import pytest
from mp_reference import reference

from flexkane.modes import get_family

XI = np.array([0.0, 0.013, 0.25, 0.5, 0.77, 0.999, 1.0])


def test_modes_satisfy_the_boundary_conditions_of_eq_8_2():
    family = get_family("clamped-free")
    n = 30
    lam = family.roots(n)
    root, tip = np.zeros(1), np.ones(1)
    for k, end in ((0, root), (1, root), (2, tip), (3, tip)):
        value = family.phi(end, n, k)[:, 0] / lam ** k
        assert np.all(np.abs(value) < 1e-13), k


def test_modes_satisfy_the_beam_equation_8_1():
    family = get_family("clamped-free")
    xi = np.linspace(0, 1, 11)
    lam = family.roots(8)
    np.testing.assert_allclose(family.phi(xi, 8, 4), lam[:, None] ** 4 * family.phi(xi, 8, 0),
                               atol=1e-12 * lam[-1] ** 4)


def test_tip_deflection_alternates_plus_minus_two_and_root_curvature_is_positive():
    family = get_family("clamped-free")
    n = 50
    tip = family.phi(1.0, n)[:, 0]
    np.testing.assert_allclose(tip, 2.0 * (-1.0) ** np.arange(n), atol=1e-12)
    curvature = family.phi(0.0, n, 2)[:, 0]
    np.testing.assert_allclose(curvature, 2.0 * family.roots(n) ** 2, rtol=1e-13)


def test_mode_50_and_four_derivatives_match_a_120_digit_evaluation_of_eq_8_4():
    family = get_family("clamped-free")
    lam50 = family.roots(50)[-1]
    root, exact = reference("clamped-free", 50, lam50, XI)
    assert lam50 == pytest.approx(root, rel=4e-16)
    for k in range(5):
        got = family.phi(XI, 50, k)[-1]
        scale = np.abs(exact[k]).max()
        assert np.abs(got - exact[k]).max() < 1e-10 * scale, k


def test_textbook_form_loses_its_digits_where_the_stable_form_does_not():
    # eq. 8.4 evaluated naively in double precision: useless by i = 20, as the issue says
    family = get_family("clamped-free")
    lam = family.roots(20)[-1]
    a = lam * XI
    sigma = (np.cosh(lam) + np.cos(lam)) / (np.sinh(lam) + np.sin(lam))
    naive = np.cosh(a) - np.cos(a) - sigma * (np.sinh(a) - np.sin(a))
    _, exact = reference("clamped-free", 20, lam, XI)
    assert np.abs(naive - exact[0]).max() > 1e-3
    assert np.abs(family.phi(XI, 20)[-1] - exact[0]).max() < 1e-12


def test_typed_root_reproduces_eq_8_4_as_written():
    # the chapter's notebook types lam1 = 1.875
    family = get_family("clamped-free", roots=[1.875])
    lam = 1.875
    xi = np.linspace(0, 1, 21)
    a = lam * xi
    sigma = (np.cosh(lam) + np.cos(lam)) / (np.sinh(lam) + np.sin(lam))
    textbook = np.cosh(a) - np.cos(a) - sigma * (np.sinh(a) - np.sin(a))
    np.testing.assert_allclose(family.phi(xi, 1)[0], textbook, rtol=1e-14, atol=1e-15)
    second = lam ** 2 * (np.cosh(a) + np.cos(a) - sigma * (np.sinh(a) + np.sin(a)))
    np.testing.assert_allclose(family.phi(xi, 1, 2)[0], second, rtol=1e-14, atol=1e-14)
    assert family.roots(1)[0] == 1.875


def test_typed_root_is_not_renormalised():
    typed = get_family("clamped-free", roots=[1.875]).phi(1.0, 1)[0, 0]
    exact = get_family("clamped-free").phi(1.0, 1)[0, 0]
    assert typed != exact
    assert typed == pytest.approx(exact, rel=1e-3)


def test_typed_roots_limit_the_number_of_modes():
    from flexkane.errors import ModelError

    family = get_family("clamped-free", roots=[1.875, 4.694])
    assert family.phi(0.5, 2).shape == (2, 1)
    with pytest.raises(ModelError, match="at most 2"):
        family.phi(0.5, 3)


def test_phi_has_shape_modes_by_points_for_scalars_and_arrays():
    family = get_family("clamped-free")
    assert family.phi(0.3, 4).shape == (4, 1)
    assert family.phi(np.linspace(0, 1, 7), 4, 3).shape == (4, 7)
