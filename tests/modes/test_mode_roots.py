"""Roots of the frequency equations: published values, full precision, limits of the tip mass."""

import math

import mpmath as mp
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from flexkane.modes import get_family

PUBLISHED = {
    # eq. 8.6; Blevins, Formulas for natural frequency and mode shape, table 8-1
    "clamped-free": [1.8751040687, 4.6940911330, 7.8547574382, 10.995540735],
    # (7.0685827611, sometimes quoted, is wrong in the 9th digit: tan l - tanh l = 0 at 7.0685827456)
    "pinned-free": [3.9266023120, 7.0685827456],
    "clamped-clamped": [4.7300407449, 7.8532046241],
    "free-free": [4.7300407449, 7.8532046241],
    "clamped-pinned": [3.9266023120, 7.0685827456],
    "pinned-pinned": [math.pi, 2 * math.pi, 3 * math.pi],
    "axial-fixed-free": [math.pi / 2, 3 * math.pi / 2],
    "axial-fixed-fixed": [math.pi, 2 * math.pi],
}


@pytest.mark.parametrize("name", sorted(PUBLISHED))
def test_roots_match_published_values(name):
    published = np.array(PUBLISHED[name])
    roots = get_family(name).roots(len(published))
    np.testing.assert_allclose(roots, published, rtol=2e-11)


def test_cantilever_roots_solve_eq_8_6_to_full_double_precision():
    roots = get_family("clamped-free").roots(60)
    with mp.workdps(50):
        for i in (1, 2, 3, 10, 25, 60):
            exact = mp.findroot(lambda l: mp.cos(l) + mp.sech(l), roots[i - 1])
            assert abs(roots[i - 1] - float(exact)) <= 2 * np.spacing(float(exact))


@pytest.mark.parametrize("name, equation", [
    ("clamped-clamped", lambda l: mp.cos(l) - mp.sech(l)),
    ("pinned-free", lambda l: mp.sin(l) - mp.cos(l) * mp.tanh(l)),
])
def test_other_roots_are_correctly_rounded(name, equation):
    roots = get_family(name).roots(50)
    with mp.workdps(50):
        for i in (1, 7, 50):
            exact = float(mp.findroot(equation, roots[i - 1]))
            assert abs(roots[i - 1] - exact) <= 2 * np.spacing(exact)


def test_roots_are_increasing_and_approach_the_asymptote():
    roots = get_family("clamped-free").roots(40)
    assert np.all(np.diff(roots) > 0)
    asymptote = (2 * np.arange(1, 41) - 1) * np.pi / 2
    assert abs(roots[-1] - asymptote[-1]) < 1e-30 + 1e-15 * asymptote[-1]


def test_asking_for_more_roots_extends_without_changing_the_first():
    family = get_family("clamped-free")
    first = family.roots(3)
    np.testing.assert_array_equal(family.roots(20)[:3], first)


def test_tip_mass_family_without_tip_body_is_the_cantilever():
    tip = get_family("clamped-free-tip-mass", mass_ratio=0.0, inertia_ratio=0.0)
    np.testing.assert_allclose(tip.roots(6), get_family("clamped-free").roots(6), rtol=1e-15)


@pytest.mark.parametrize("mu", [1e-6, 1e-9])
def test_tip_mass_roots_tend_to_cantilever_roots_as_mass_ratio_vanishes(mu):
    tip = get_family("clamped-free-tip-mass", mass_ratio=mu, inertia_ratio=0.0)
    np.testing.assert_allclose(tip.roots(5), get_family("clamped-free").roots(5), rtol=20 * mu)


def test_heavy_tip_mass_higher_roots_tend_to_clamped_pinned_roots():
    clamped_pinned = get_family("clamped-pinned").roots(4)
    for mu, tol in ((1e4, 1e-5), (1e8, 1e-9)):
        roots = get_family("clamped-free-tip-mass", mass_ratio=mu, inertia_ratio=0.0).roots(5)
        np.testing.assert_allclose(roots[1:], clamped_pinned, rtol=tol)


def test_heavy_tip_mass_first_mode_is_a_mass_on_the_cantilever_spring():
    # Rayleigh: p^2 = 3 EI / (L^3 (M + 33/140 rho L))  ->  lambda^4 (mu + 33/140) -> 3
    for mu in (1e2, 1e4):
        lam1 = get_family("clamped-free-tip-mass", mass_ratio=mu, inertia_ratio=0.0).roots(1)[0]
        assert lam1 ** 4 * (mu + 33 / 140) == pytest.approx(3.0, rel=1e-6)


def test_tip_mass_equal_to_beam_mass_matches_published_roots():
    # Blevins, table 8-1 case 4 (M / (rho L) = 1)
    roots = get_family("clamped-free-tip-mass", mass_ratio=1.0, inertia_ratio=0.0).roots(2)
    np.testing.assert_allclose(roots, [1.24792, 4.03114], atol=1e-5)


def test_large_tip_inertia_gives_the_clamped_guided_roots():
    # a rotation-locked tip with free shear: tan l + tanh l = 0 (2.36502, 5.49780)
    roots = get_family("clamped-free-tip-mass", mass_ratio=0.0, inertia_ratio=1e12).roots(3)
    np.testing.assert_allclose(roots[1:], [2.3650203, 5.4978039], rtol=1e-6)


@pytest.mark.parametrize("mu, kappa", [(0.5, 0.01), (2.0, 0.3), (20.0, 5.0)])
def test_tip_mass_roots_solve_the_frequency_equation(mu, kappa):
    family = get_family("clamped-free-tip-mass", mass_ratio=mu, inertia_ratio=kappa)
    roots = family.roots(12)
    assert np.all(np.diff(roots) > 0)
    # never above the cantilever's: a tip body lowers every frequency
    assert np.all(roots <= get_family("clamped-free").roots(12))
    scale = 1 + mu * roots + kappa * roots ** 3 + mu * kappa * roots ** 4
    assert np.all(np.abs(family.frequency_function(roots)) < 1e-13 * scale)


def test_frequencies_follow_eq_8_7():
    family = get_family("clamped-free")
    p = family.frequencies(3, 2.0, 35.3, 0.21991)
    np.testing.assert_allclose(p, (family.roots(3) / 2.0) ** 2 * np.sqrt(35.3 / 0.21991), rtol=1e-15)


def test_axial_frequencies_use_the_axial_rigidity():
    family = get_family("axial-fixed-free")
    p = family.frequencies(2, 2.0, 1e6, 4.0)
    np.testing.assert_allclose(p, [np.pi / 4 * 500.0, 3 * np.pi / 4 * 500.0], rtol=1e-15)


@pytest.mark.parametrize("name", ["polynomial"])
def test_families_without_eigenvalues_have_no_roots(name):
    family = get_family(name)
    assert family.roots(3) is None
    assert family.frequencies(3, 1.0, 1.0, 1.0) is None


@settings(max_examples=25, deadline=None)
@given(mu=st.floats(0.0, 50.0), extra=st.floats(1e-3, 50.0), kappa=st.floats(0.0, 2.0))
def test_a_heavier_tip_body_lowers_every_frequency(mu, extra, kappa):
    light = get_family("clamped-free-tip-mass", mass_ratio=mu, inertia_ratio=kappa).roots(6)
    heavy = get_family("clamped-free-tip-mass", mass_ratio=mu + extra, inertia_ratio=kappa).roots(6)
    assert np.all(heavy < light)
    # interlacing of a rank-one mass increase: lambda_i(heavy) > lambda_{i-1}(light)
    assert np.all(heavy[1:] > light[:-1])
