"""Every family: boundary conditions, orthonormality, sign convention, stability, registry."""

import math

import numpy as np
import pytest
from mp_reference import reference

from flexkane.errors import ModelError
from flexkane.modes import family_names, get_family
from flexkane.modes.integrals import gauss_legendre

EIGEN = ["clamped-free", "pinned-free", "pinned-pinned", "clamped-pinned", "clamped-clamped",
         "free-free"]

# derivatives that vanish at (root, tip) for each classical boundary
ZERO_AT = {
    "clamped-free": ((0, 1), (2, 3)),
    "pinned-free": ((0, 2), (2, 3)),
    "pinned-pinned": ((0, 2), (0, 2)),
    "clamped-pinned": ((0, 1), (0, 2)),
    "clamped-clamped": ((0, 1), (0, 1)),
    "free-free": ((2, 3), (2, 3)),
}


@pytest.mark.parametrize("name", EIGEN)
def test_eigenfunctions_satisfy_their_boundary_conditions(name):
    family = get_family(name)
    n = 40
    lam = family.roots(n)
    for end, orders in zip((0.0, 1.0), ZERO_AT[name]):
        for k in orders:
            value = family.phi(end, n, k)[:, 0] / lam ** k
            assert np.all(np.abs(value) < 1e-12), (end, k)


@pytest.mark.parametrize("name", EIGEN + ["axial-fixed-free", "axial-fixed-fixed"])
def test_eigenfunctions_are_orthonormal(name):
    family = get_family(name)
    n = 40
    x, w = gauss_legendre(400)
    values = family.phi(x, n)
    np.testing.assert_allclose((values * w) @ values.T, np.eye(n), atol=1e-12)


@pytest.mark.parametrize("name", EIGEN)
def test_curvatures_are_orthogonal_with_lambda_to_the_fourth(name):
    family = get_family(name)
    n = 40
    x, w = gauss_legendre(400)
    curvature = family.phi(x, n, 2)
    lam = family.roots(n)
    expected = np.diag(lam ** 4)
    np.testing.assert_allclose((curvature * w) @ curvature.T / np.outer(lam, lam) ** 2,
                               expected / np.outer(lam, lam) ** 2, atol=1e-12)


@pytest.mark.parametrize("name", EIGEN)
def test_first_nonzero_derivative_at_the_root_is_positive(name):
    family = get_family(name)
    n = 25
    lam = family.roots(n)
    order = {"clamped": 2, "pinned": 1, "free": 0}[name.split("-")[0]]
    assert np.all(family.phi(0.0, n, order)[:, 0] / lam ** order > 0.5)


@pytest.mark.parametrize("name, guess_index", [
    ("clamped-clamped", 50), ("free-free", 50), ("clamped-pinned", 50), ("pinned-free", 50)])
def test_mode_50_matches_a_high_precision_textbook_evaluation(name, guess_index):
    family = get_family(name)
    xi = np.array([0.0, 0.1, 0.5, 0.9, 1.0])
    lam = family.roots(guess_index)[-1]
    root, exact = reference(name, guess_index, lam, xi)
    assert lam == pytest.approx(root, rel=4e-16)
    for k in range(5):
        got = family.phi(xi, guess_index, k)[-1]
        assert np.abs(got - exact[k]).max() < 1e-10 * np.abs(exact[k]).max(), k


def test_tip_mass_modes_match_high_precision_and_satisfy_the_tip_conditions():
    mu, kappa = 0.5, 0.01
    family = get_family("clamped-free-tip-mass", mass_ratio=mu, inertia_ratio=kappa)
    n = 30
    lam = family.roots(n)
    xi = np.array([0.0, 0.3, 0.8, 1.0])
    root, exact = reference("clamped-free-tip-mass", n, lam[-1], xi, mu, kappa)
    assert lam[-1] == pytest.approx(root, rel=1e-15)
    for k in range(5):
        got = family.phi(xi, n, k)[-1]
        assert np.abs(got - exact[k]).max() < 1e-10 * np.abs(exact[k]).max(), k
    tip = [family.phi(1.0, n, k)[:, 0] for k in range(4)]
    # shear and moment conditions at the tip (tip_mass module docstring), divided by lambda^3
    shear = tip[3] / lam ** 3 + mu * lam * tip[0]
    moment = tip[2] / lam ** 2 - kappa * lam ** 2 * tip[1]
    assert np.all(np.abs(shear) < 1e-12 * (1 + mu * lam))
    assert np.all(np.abs(moment) < 1e-12 * (1 + kappa * lam ** 3))


def test_tip_mass_modes_are_orthonormal_with_respect_to_beam_plus_tip_body():
    mu, kappa = 2.0, 0.3
    family = get_family("clamped-free-tip-mass", mass_ratio=mu, inertia_ratio=kappa)
    n = 20
    x, w = gauss_legendre(300)
    values = family.phi(x, n)
    tip, slope = family.phi(1.0, n)[:, 0], family.phi(1.0, n, 1)[:, 0]
    mass = (values * w) @ values.T + mu * np.outer(tip, tip) + kappa * np.outer(slope, slope)
    np.testing.assert_allclose(mass, np.eye(n), atol=1e-12)
    curvature = family.phi(x, n, 2)
    lam = family.roots(n)
    stiffness = (curvature * w) @ curvature.T / np.outer(lam, lam) ** 2
    np.testing.assert_allclose(stiffness, np.eye(n), atol=1e-12)


@pytest.mark.parametrize("name", ["free-free", "pinned-free"])
def test_rigid_modes_are_orthonormal_and_orthogonal_to_elastic_modes(name):
    family = get_family(name)
    x, w = gauss_legendre(300)
    rigid = family.rigid_phi(x)
    elastic = family.phi(x, 30)
    np.testing.assert_allclose((rigid * w) @ rigid.T, np.eye(len(family.rigid_modes)), atol=1e-14)
    assert np.abs((rigid * w) @ elastic.T).max() < 1e-12
    # zero curvature: they carry no strain energy
    assert np.abs(family.rigid_phi(x, 2)).max() == 0.0


def test_free_free_has_two_rigid_modes_and_phi_starts_with_the_first_elastic_mode():
    family = get_family("free-free")
    assert [m.name for m in family.rigid_modes] == ["translation", "rotation about the centre"]
    assert family.phi(0.0, 1).shape == (1, 1)
    assert family.roots(1)[0] == pytest.approx(4.7300407449)


def test_pinned_pinned_modes_are_root_two_sines():
    xi = np.linspace(0, 1, 9)
    np.testing.assert_allclose(get_family("pinned-pinned").phi(xi, 3),
                               math.sqrt(2) * np.sin(np.outer([1, 2, 3], xi) * np.pi), atol=1e-15)


def test_axial_fixed_free_modes_are_root_two_quarter_sines():
    xi = np.linspace(0, 1, 9)
    family = get_family("axial-fixed-free")
    assert family.kind == "axial"
    np.testing.assert_allclose(family.phi(xi, 2, 1),
                               math.sqrt(2) * np.array([np.pi / 2 * np.cos(np.pi / 2 * xi),
                                                        3 * np.pi / 2 * np.cos(3 * np.pi / 2 * xi)]),
                               atol=1e-14)


def test_polynomial_family_is_the_monomials_from_xi_squared():
    family = get_family("polynomial")
    xi = np.linspace(0, 1, 5)
    np.testing.assert_allclose(family.phi(xi, 3), np.vstack([xi ** 2, xi ** 3, xi ** 4]))
    np.testing.assert_allclose(family.phi(xi, 3, 2), np.vstack([2 + 0 * xi, 6 * xi, 12 * xi ** 2]))
    np.testing.assert_allclose(family.phi(xi, 3, 4), np.vstack([0 * xi, 0 * xi, 24 + 0 * xi]))
    family.admissibility("clamped-free")


def test_registry_lists_every_family_named_in_the_design():
    assert set(family_names()) == {
        "clamped-free", "pinned-free", "pinned-pinned", "clamped-pinned", "clamped-clamped",
        "free-free", "clamped-free-tip-mass", "polynomial", "expression", "axial-fixed-free",
        "axial-fixed-fixed", "torsion-clamped-free", "torsion-clamped-clamped", "torsion-free-free",
        "torsion-polynomial", "axial-polynomial"}


def test_unknown_family_name_lists_the_valid_names():
    with pytest.raises(ModelError) as info:
        get_family("cantilever")
    assert info.value.path == "family"
    assert "clamped-free" in str(info.value) and "cantilever" in str(info.value)


def test_unknown_option_is_an_error_naming_it():
    with pytest.raises(ModelError) as info:
        get_family("clamped-clamped", roots=[4.73])
    assert info.value.path == "roots"


def test_tip_mass_family_requires_both_ratios():
    with pytest.raises(ModelError, match="inertia_ratio"):
        get_family("clamped-free-tip-mass", mass_ratio=1.0)
    with pytest.raises(ModelError, match="mass_ratio"):
        get_family("clamped-free-tip-mass", mass_ratio=-1.0, inertia_ratio=0.0)


@pytest.mark.parametrize("bad", [[], [-1.0], ["x"], [float("nan")]])
def test_typed_roots_must_be_positive_numbers(bad):
    with pytest.raises(ModelError) as info:
        get_family("clamped-free", roots=bad)
    assert info.value.path == "roots"


def test_equal_names_and_options_give_equal_hashable_families():
    a = get_family("clamped-free-tip-mass", mass_ratio=1, inertia_ratio=0.5)
    b = get_family("clamped-free-tip-mass", mass_ratio=1.0, inertia_ratio=0.5)
    c = get_family("clamped-free-tip-mass", mass_ratio=1.0, inertia_ratio=0.25)
    assert a == b and hash(a) == hash(b) and a != c
    assert get_family("clamped-free", roots=[1.875]) != get_family("clamped-free")


@pytest.mark.parametrize("call, path", [
    (lambda f: f.phi([0.5, 1.5], 2), "xi"),
    (lambda f: f.phi(0.5, 0), "n"),
    (lambda f: f.phi(0.5, 2, 5), "deriv"),
    (lambda f: f.frequencies(2, 1.0, -1.0, 1.0), "EI"),
])
def test_bad_arguments_raise_model_errors_naming_them(call, path):
    with pytest.raises(ModelError) as info:
        call(get_family("clamped-free"))
    assert info.value.path == path


def test_abscissae_rounded_past_the_ends_are_accepted():
    family = get_family("clamped-free")
    np.testing.assert_array_equal(family.phi([1.0 + 2e-16, -1e-17], 3),
                                  family.phi([1.0, 0.0], 3))


def test_admissibility_accepts_the_family_boundary_and_rejects_a_stricter_one():
    get_family("clamped-free").admissibility("clamped-free")
    get_family("clamped-pinned").admissibility("clamped-pinned")
    with pytest.raises(ModelError, match="Phi"):
        get_family("pinned-free").admissibility("clamped")
