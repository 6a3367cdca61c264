"""A beam clamped on the axis of a hub spinning at a constant rate Omega, bending in the plane of the spin.

In the rotating frame the centrifugal tension T(x) = rho Omega^2 (L^2 - x^2) / 2 stiffens the beam,
by K Omega^2 in the first mode with K the Rayleigh quotient int T Phi'^2 / (Omega^2 int rho Phi^2)
(the Southwell coefficient, about 1.193 for the first cantilever mode), and the centrifugal force
across the deflected beam softens it by Omega^2 (in-plane bending). So, in the first mode,
w^2 ~ w0^2 + (K - 1) Omega^2 with geometric stiffening (``spin-up``) and, without it (``spin-up-linear``,
the chapter's linear formulation), w_i^2 = p_i^2 - Omega^2 exactly: the beam buckles (diverges) once
Omega exceeds p_1.
"""

import numpy as np
import pytest

import flexkane
from flexkane.analysis import campbell_diagram, linearize, modal_analysis
from flexkane.modes import get_family
from flexkane.modes.integrals import gauss_legendre

SPINS = [0.0, 2.0, 4.0, 6.0]


def southwell_coefficient():
    """Rayleigh quotient of the centrifugal stiffness of the first cantilever mode (L = 1)."""
    xi, w = gauss_legendre(60)
    family = get_family("clamped-free")
    slope = family.phi(xi, 1, 1)[0]
    shape = family.phi(xi, 1)[0]
    return float(np.sum(w * (1 - xi ** 2) / 2 * slope ** 2) / np.sum(w * shape ** 2))


def first_bending_frequency():
    model = flexkane.builtin_model("spin-up")
    values = flexkane.derive(model).constant_values()
    by_name = {s.name: v for s, v in values.items()}
    return get_family("clamped-free").frequencies(1, by_name["L"], by_name["EI"], by_name["rho"])[0]


def test_rayleigh_quotient_of_the_first_cantilever_mode_is_the_southwell_coefficient():
    assert southwell_coefficient() == pytest.approx(1.193, abs=5e-4)


def test_one_mode_rotating_beam_follows_the_southwell_estimate():
    w0 = first_bending_frequency()
    K = southwell_coefficient()
    diagram = campbell_diagram(flexkane.builtin_model("spin-up").with_modes(1), SPINS)
    np.testing.assert_allclose(diagram.frequencies[:, 0] ** 2, w0 ** 2 + (K - 1) * np.array(SPINS) ** 2,
                               rtol=1e-9)


def test_first_frequency_of_spin_up_rises_with_spin_and_compares_with_southwell():
    w0 = first_bending_frequency()
    estimate = np.sqrt(w0 ** 2 + (southwell_coefficient() - 1) * np.array(SPINS) ** 2)
    diagram = campbell_diagram(flexkane.builtin_model("spin-up"), SPINS)   # four modes
    first = diagram.frequencies[:, 0]
    assert first[0] == pytest.approx(w0, rel=1e-10)
    assert np.all(np.diff(first) > 0)
    # more modes, lower Rayleigh-Ritz values: at most the one-mode estimate, and close to it
    assert np.all(first <= estimate * (1 + 1e-12))
    np.testing.assert_allclose(first, estimate, rtol=0.03)
    assert first[1] == pytest.approx(estimate[1], rel=1e-3)
    assert not diagram.unstable.any()


def test_linear_rotating_beam_softens_by_omega_squared_and_diverges_past_its_first_frequency():
    model = flexkane.builtin_model("spin-up-linear")
    n = 4
    p = modal_analysis(linearize(model)).frequencies
    diagram = campbell_diagram(model, SPINS)
    assert p[0] == pytest.approx(3.80, abs=0.005)
    for k, spin in enumerate(SPINS):
        if spin < p[0]:
            np.testing.assert_allclose(diagram.frequencies[k] ** 2, p ** 2 - spin ** 2, rtol=1e-9)
            assert diagram.growth_rates[k] == 0.0
        else:
            assert diagram.frequencies[k, 0] == 0.0
            np.testing.assert_allclose(diagram.frequencies[k, 1:n] ** 2, p[1:] ** 2 - spin ** 2, rtol=1e-9)
            assert diagram.growth_rates[k] == pytest.approx(np.sqrt(spin ** 2 - p[0] ** 2), rel=1e-9)
    assert list(diagram.unstable) == [s > p[0] for s in SPINS]
