"""Free vibration by modal superposition (eqs. 8.3, 8.5) and Rayleigh-Ritz statics."""

import numpy as np
import pytest

from flexkane.errors import ModelError
from flexkane.modes import get_family
from flexkane.modes.free_vibration import (FreeVibration, rayleigh_ritz_frequencies,
                                           static_tip_load_coordinates, tip_load_shape)

L, EI, RHO, P = 1.0, 35.3, 0.21991, 2.0
STATIC_TIP = P * L ** 3 / (3 * EI)


def test_released_tip_load_shape_converges_to_the_static_tip_deflection():
    family = get_family("clamped-free")
    errors = []
    for n in (2, 4, 8, 16, 32):
        vibration = FreeVibration.from_tip_load(family, n, L, EI, RHO, P)
        errors.append(abs(vibration.deflection([L], [0.0])[0, 0] / STATIC_TIP - 1))
    # alpha_i = 4 P L^3 / (EI lambda_i^4) (+-), so the truncation error falls like n^-3
    assert errors[-1] < 2e-6
    observed_order = np.polyfit(np.log([2, 4, 8, 16, 32][1:]), np.log(errors[1:]), 1)[0]
    assert observed_order == pytest.approx(-3.0, abs=0.2)


def test_tip_load_coefficients_have_the_closed_form():
    family = get_family("clamped-free")
    n = 10
    vibration = FreeVibration.from_tip_load(family, n, L, EI, RHO, P)
    lam = family.roots(n)
    expected = P * L ** 3 / EI * family.phi(1.0, n)[:, 0] / lam ** 4
    np.testing.assert_allclose(vibration.alpha, expected, rtol=1e-10, atol=1e-16)
    np.testing.assert_array_equal(vibration.beta, np.zeros(n))


def test_initial_shape_is_reproduced_as_the_number_of_modes_grows():
    family = get_family("clamped-free")
    # static shape under a uniform load
    shape = lambda xi: 1e-3 * xi ** 2 * (6 - 4 * xi + xi ** 2)  # noqa: E731
    x = np.linspace(0, L, 41)
    errors = [np.abs(FreeVibration(family, n, L, EI, RHO, shape, None).deflection(x, 0.0)[0]
                     - shape(x / L)).max() for n in (2, 6, 18)]
    assert errors[0] > errors[1] > errors[2]
    assert errors[2] < 1e-4 * np.abs(shape(x / L)).max()


def test_initial_velocity_is_reproduced_and_sets_beta():
    family = get_family("pinned-pinned")
    v0 = lambda xi: 0.3 * np.sqrt(2) * np.sin(2 * np.pi * xi)  # noqa: E731
    vibration = FreeVibration(family, 5, L, EI, RHO, lambda xi: 0 * xi, v0)
    p = vibration.frequencies
    np.testing.assert_allclose(vibration.beta, [0, 0.3 / p[1], 0, 0, 0], atol=1e-14)
    x = np.linspace(0, L, 7)
    np.testing.assert_allclose(vibration.velocity(x, 0.0)[0], v0(x / L), atol=1e-13)


def test_a_single_mode_oscillates_at_its_natural_frequency():
    family = get_family("clamped-free")
    vibration = FreeVibration(family, 4, L, EI, RHO, lambda xi: 0.01 * family.phi(xi, 2)[1], None)
    period = 2 * np.pi / vibration.frequencies[1]
    x = np.array([0.5 * L, L])
    np.testing.assert_allclose(vibration.deflection(x, [period, 2 * period]),
                               vibration.deflection(x, [0.0, 0.0]), atol=1e-12)
    np.testing.assert_allclose(vibration.deflection(x, period / 2), -vibration.deflection(x, 0.0),
                               atol=1e-12)


def test_free_free_beam_drifts_with_its_rigid_modes():
    family = get_family("free-free")
    vibration = FreeVibration(family, 6, L, EI, RHO, lambda xi: 0 * xi, lambda xi: 0.5 + 0 * xi)
    np.testing.assert_allclose(vibration.beta, np.zeros(6), atol=1e-14)
    np.testing.assert_allclose(vibration.deflection([0.0, L], 2.0), [[1.0, 1.0]], rtol=1e-13)


@pytest.mark.parametrize("name", ["polynomial", "axial-fixed-free"])
def test_families_without_transverse_eigenvalues_are_refused(name):
    with pytest.raises(ModelError) as info:
        FreeVibration(get_family(name), 3, L, EI, RHO, lambda xi: xi ** 2, None)
    assert info.value.path == "family"


def test_tip_load_release_requires_a_cantilever():
    with pytest.raises(ModelError, match="clamped-free"):
        FreeVibration.from_tip_load(get_family("pinned-pinned"), 3, L, EI, RHO, P)


def test_two_polynomials_give_the_exact_static_tip_deflection():
    family = get_family("polynomial")
    for n in (2, 3, 5):
        q = static_tip_load_coordinates(family, n, L, EI, P)
        assert q @ family.phi(1.0, n)[:, 0] == pytest.approx(STATIC_TIP, rel=1e-12)
    one = static_tip_load_coordinates(family, 1, L, EI, P)
    assert one[0] == pytest.approx(0.75 * STATIC_TIP, rel=1e-13)  # xi^2 alone: 1/4 too soft


def test_polynomial_shape_is_the_exact_static_shape():
    family = get_family("polynomial")
    q = static_tip_load_coordinates(family, 2, L, EI, P)
    xi = np.linspace(0, 1, 9)
    np.testing.assert_allclose(q @ family.phi(xi, 2), tip_load_shape(L, EI, P)(xi), rtol=1e-12,
                               atol=1e-16)


def test_cantilever_modes_give_the_static_tip_deflection_as_n_grows():
    family = get_family("clamped-free")
    tips = [static_tip_load_coordinates(family, n, L, EI, P) @ family.phi(1.0, n)[:, 0]
            for n in (4, 16)]
    assert abs(tips[1] / STATIC_TIP - 1) < abs(tips[0] / STATIC_TIP - 1) < 1e-3


def test_ritz_frequencies_of_polynomials_bound_the_cantilever_frequencies_from_above():
    exact = get_family("clamped-free").frequencies(3, L, EI, RHO)
    ritz = rayleigh_ritz_frequencies(get_family("polynomial"), 6, L, EI, RHO)[:3]
    assert np.all(ritz >= exact * (1 - 1e-12))
    assert ritz[0] == pytest.approx(exact[0], rel=1e-6)


def test_ritz_frequencies_of_eigenfunctions_are_eq_8_7():
    family = get_family("clamped-clamped")
    np.testing.assert_allclose(rayleigh_ritz_frequencies(family, 8, L, EI, RHO),
                               family.frequencies(8, L, EI, RHO), rtol=1e-11)


def test_a_plucked_beam_with_a_kink_is_projected():
    # triangular pluck of a simply supported beam: alpha_k = 8 h sin(k pi / 2) / (k pi)^2 / sqrt(2)
    family = get_family("pinned-pinned")
    h = 0.01
    pluck = lambda xi: h * (1 - np.abs(2 * xi - 1))  # noqa: E731
    vibration = FreeVibration(family, 7, L, EI, RHO, pluck, None)
    k = np.arange(1, 8)
    expected = 8 * h * np.sin(k * np.pi / 2) / (k * np.pi) ** 2 / np.sqrt(2)
    np.testing.assert_allclose(vibration.alpha, expected, rtol=0, atol=1e-11 * h)
