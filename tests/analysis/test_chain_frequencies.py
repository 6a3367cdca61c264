"""Natural frequencies of whole chains against closed-form beam theory.

* A uniform beam clamped to a hub of inertia J_h turning freely on a fixed axis (no gravity, no
  torque): besides the rigid rotation, w = beta^2 sqrt(EI/(rho L^4)) with
  gamma beta^3 (1 + cos beta cosh beta) + (sin beta cosh beta - cos beta sinh beta) = 0,
  gamma = J_h/(rho L^3). (Boundary conditions w(0) = 0, w'(0) = theta, J_h theta'' = EI w''(0),
  free tip; the 3 x 3 determinant of the Euler-Bernoulli solution gives the equation.)
* A cantilever on a fixed base: p_i of eq. 8.7.
"""

import numpy as np
import pytest
from scipy.optimize import brentq

from flexkane import Model
from flexkane.analysis import linearize, modal_analysis
from flexkane.model.parts import Beam, Joint, RigidBody
from flexkane.modes import get_family


def hub_characteristic(beta, gamma):
    """gamma beta^3 (1 + cos cosh) + (sin cosh - cos sinh), divided by cosh beta to stay O(1)."""
    c, s = np.cos(beta), np.sin(beta)
    return gamma * beta ** 3 * (1 / np.cosh(beta) + c) + (s - c * np.tanh(beta))


def hub_roots(gamma, count):
    """First ``count`` positive roots beta of the characteristic equation, by bracketing and brentq."""
    grid = np.linspace(0.3, 4 * (count + 2), 20000)
    values = hub_characteristic(grid, gamma)
    roots = [brentq(hub_characteristic, a, b, args=(gamma,), xtol=1e-15, rtol=1e-15)
             for a, b, fa, fb in zip(grid[:-1], grid[1:], values[:-1], values[1:]) if fa * fb < 0]
    return np.array(roots[:count])


def hub_beam_model(gamma, n_modes, L=1.0, EI=1.0, rho=1.0):
    model = Model(name="hub-beam", parameters={"L": L, "EI": EI, "rho": rho, "J_h": gamma * rho * L ** 3,
                                               "m_h": 1.0})
    model.bodies["hub"] = RigidBody(name="hub", mass="m_h", inertia="J_h")
    model.beams["B"] = Beam(name="B", L="L", EI="EI", rho="rho", n_modes=n_modes)
    model.joints["axis"] = Joint(name="axis", type="revolute", parent="ground", child="hub")
    model.joints["clamp"] = Joint(name="clamp", type="weld", parent="hub", child="B")
    return model


def cantilever_model(n_modes, L, EI, rho):
    model = Model(name="cantilever", parameters={"L": L, "EI": EI, "rho": rho})
    model.beams["B"] = Beam(name="B", L="L", EI="EI", rho="rho", n_modes=n_modes)
    model.joints["clamp"] = Joint(name="clamp", type="weld", parent="ground", child="B")
    return model


def test_hub_characteristic_roots_tend_to_pinned_free_and_clamped_free_roots():
    pinned_free = get_family("pinned-free").roots(3)
    clamped_free = get_family("clamped-free").roots(3)
    np.testing.assert_allclose(hub_roots(1e-9, 3), pinned_free, rtol=1e-7)
    np.testing.assert_allclose(hub_roots(1e9, 3), clamped_free, rtol=1e-7)
    # and they lie in between for finite hubs, decreasing as the hub gets heavier
    roots = [hub_roots(g, 3) for g in (0.01, 0.1, 1.0, 10.0)]
    for r in roots:
        assert np.all(r < pinned_free) and np.all(r > clamped_free)
    assert np.all(np.diff(np.array(roots), axis=0) < 0)


@pytest.mark.parametrize("gamma", [0.01, 0.1, 1.0, 10.0])
def test_beam_on_free_hub_frequencies_converge_to_the_characteristic_roots(gamma):
    exact = hub_roots(gamma, 2) ** 2            # L = EI = rho = 1: w = beta^2
    errors = []
    for n in (2, 4, 8):
        modal = modal_analysis(linearize(hub_beam_model(gamma, n)))
        assert len(modal.rigid) == 1
        rigid = modal.rigid[0].shape
        assert abs(rigid[0]) == pytest.approx(1.0) and np.allclose(rigid[1:], 0.0)   # hub turns, beam straight
        errors.append((modal.frequencies[:2] - exact) / exact)
    errors = np.array(errors)
    assert np.all(errors > -1e-12)                 # Rayleigh-Ritz values bound the exact ones from above
    assert np.all(np.diff(errors, axis=0) < 0)     # and decrease towards them as modes are added
    assert np.max(errors[-1]) < 1e-6


def test_cantilever_on_fixed_base_has_the_frequencies_of_eq_8_7():
    L, EI, rho, n = 1.3, 35.3, 0.21991, 6
    modal = modal_analysis(linearize(cantilever_model(n, L, EI, rho)))
    p = get_family("clamped-free").frequencies(n, L, EI, rho)
    assert not modal.rigid
    np.testing.assert_allclose(modal.frequencies, p, rtol=1e-10)
    for i, mode in enumerate(modal.modes):            # each system mode is one shape function
        expected = np.zeros(n)
        expected[i] = 1.0
        np.testing.assert_allclose(mode.shape, expected, atol=1e-9)
        assert mode.damping_ratio == 0.0
        assert mode.frequency == pytest.approx(p[i] / (2 * np.pi), rel=1e-10)
