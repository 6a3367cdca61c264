"""DOP853 loop: agreement with SciPy, accuracy of the dense output, observed order."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from flexkane.numerics import Status, dop853, integrate

PENDULUM_P = np.array([1.0, 1.0, 9.81])          # m [kg], l [m], g [m/s^2]
DOUBLE_PENDULUM_P = np.array([1.0, 1.5, 1.0, 0.7, 9.81])  # m1, m2 [kg], l1, l2 [m], g [m/s^2]


def test_dop853_tableau_is_consistent():
    a, b, c = dop853.DOP853_A, dop853.DOP853_B, dop853.DOP853_C
    np.testing.assert_allclose(a.sum(axis=1)[:12], c[:12], atol=1e-13)
    np.testing.assert_allclose(a.sum(axis=1)[13:], c[13:], atol=1e-13)
    assert b.sum() == pytest.approx(1.0, abs=1e-14)
    assert b @ c[:12] ** 7 == pytest.approx(1 / 8, abs=1e-14)  # order 8 quadrature condition


def _scipy_reference(module, y0, t, p):
    def fun(time, y):
        dy = np.empty_like(y)
        module.rhs(time, y, p, dy)
        return dy

    sol = solve_ivp(fun, (t[0], t[-1]), y0, method="DOP853", rtol=1e-12, atol=1e-12, t_eval=t)
    assert sol.success
    return sol.y.T


@pytest.mark.parametrize("which", ["pendulum", "double_pendulum"])
def test_dop853_matches_scipy_dop853(which, request):
    module = request.getfixturevalue(f"{which}_module")
    p = PENDULUM_P if which == "pendulum" else DOUBLE_PENDULUM_P
    y0 = np.array([2.5, 0.0]) if which == "pendulum" else np.array([1.0, 2.0, 0.0, 0.0])
    t = np.linspace(0.0, 5.0, 251)
    result = integrate(module, y0, t, p, rtol=1e-12, atol=1e-12, method="dop853")
    assert result.status == Status.OK and result.n_valid == t.size
    np.testing.assert_allclose(result.y, _scipy_reference(module, y0, t, p), rtol=0, atol=1e-9)


def test_dense_output_at_non_step_times_matches_harmonic_oscillator(oscillator_module):
    m, k = 2.0, 50.0
    omega = np.sqrt(k / m)
    t = np.sort(np.random.default_rng(3).uniform(0.0, 10.0, 997))
    t = np.concatenate([[0.0], t])
    result = integrate(oscillator_module, [1.0, 0.0], t, [m, k], rtol=1e-12, atol=1e-12,
                       method="dop853")
    assert result.naccept < t.size  # most rows fall between steps
    exact = np.column_stack([np.cos(omega * t), -omega * np.sin(omega * t)])
    np.testing.assert_allclose(result.y, exact, rtol=0, atol=1e-9)


def test_rows_do_not_depend_on_the_output_grid(oscillator_module):
    coarse = np.linspace(0.0, 4.0, 5)
    fine = np.linspace(0.0, 4.0, 401)
    a = integrate(oscillator_module, [1.0, 0.0], coarse, [2.0, 50.0], rtol=1e-10, atol=1e-10,
                  method="dop853")
    b = integrate(oscillator_module, [1.0, 0.0], fine, [2.0, 50.0], rtol=1e-10, atol=1e-10,
                  method="dop853")
    np.testing.assert_allclose(a.y, b.y[::100], atol=1e-8)


def test_observed_order_of_dop853_is_eight(oscillator_module):
    """Fit log(global error) against log(steps): the slope is -order (as diffrax's test)."""
    m, k = 2.0, 50.0
    t = np.linspace(0.0, 20.0, 3)
    steps, errors, tolerances = [], [], []
    for tol in 10.0 ** -np.arange(5.0, 11.0):
        r = integrate(oscillator_module, [1.0, 0.0], t, [m, k], rtol=tol, atol=tol,
                      method="dop853")
        steps.append(r.naccept)
        errors.append(abs(r.y[-1, 0] - np.cos(np.sqrt(k / m) * t[-1])))
        tolerances.append(tol)
    order = -np.polyfit(np.log(steps), np.log(errors), 1)[0]
    proportionality = np.polyfit(np.log(tolerances), np.log(errors), 1)[0]
    assert 7.0 < order < 10.0
    assert 0.8 < proportionality < 1.2
