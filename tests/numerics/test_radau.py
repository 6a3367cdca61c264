"""Radau IIA loop: stiff problems against the matrix exponential, cost, order."""

from __future__ import annotations

import numpy as np
from scipy.linalg import expm

from flexkane.numerics import Status, integrate


def test_radau_solves_stiff_chain_with_far_fewer_evaluations(models, stiff_chain_module):
    p, y0 = models.STIFF_CHAIN_CONSTANTS, models.STIFF_CHAIN_Y0
    A = models.stiff_chain_matrix(p)
    assert np.abs(np.linalg.eigvals(A)).max() > 0.9e6
    t = np.linspace(0.0, 2.0, 201)
    exact = np.array([expm(A * time) @ y0 for time in t])
    radau = integrate(stiff_chain_module, y0, t, p, rtol=1e-8, atol=1e-10, method="radau")
    dop = integrate(stiff_chain_module, y0, t, p, rtol=1e-8, atol=1e-10, method="dop853")
    assert radau.status == dop.status == Status.OK
    np.testing.assert_allclose(radau.y, exact, rtol=0, atol=1e-7)
    np.testing.assert_allclose(dop.y, exact, rtol=0, atol=1e-5)
    assert radau.nfev * 50 < dop.nfev


def test_observed_order_of_radau_at_step_points_is_five(models, stiff_chain_module):
    p, y0 = models.STIFF_CHAIN_CONSTANTS, models.STIFF_CHAIN_Y0
    t = np.array([0.0, 2.0])
    exact = expm(models.stiff_chain_matrix(p) * t[-1]) @ y0
    steps, errors = [], []
    for tol in 10.0 ** -np.arange(4.0, 9.0):
        r = integrate(stiff_chain_module, y0, t, p, rtol=tol, atol=tol, method="radau")
        steps.append(r.naccept)
        errors.append(np.abs(r.y[-1] - exact).max())
    order = -np.polyfit(np.log(steps), np.log(errors), 1)[0]
    assert 4.0 < order < 6.5


def test_radau_matches_dop853_on_double_pendulum(double_pendulum_module):
    p = np.array([1.0, 1.5, 1.0, 0.7, 9.81])
    t = np.linspace(0.0, 3.0, 61)
    y0 = [1.0, 2.0, 0.0, 0.0]
    radau = integrate(double_pendulum_module, y0, t, p, rtol=1e-10, atol=1e-10, method="radau")
    dop = integrate(double_pendulum_module, y0, t, p, rtol=1e-12, atol=1e-12, method="dop853")
    np.testing.assert_allclose(radau.y, dop.y, atol=1e-6)
