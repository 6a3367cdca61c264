"""Radau IIA loop: stiff problems against the matrix exponential, cost, order."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.linalg import expm

from flexkane.numerics import Status, integrate
from flexkane.numerics import radau


def test_radau_constants_are_those_of_the_three_stage_radau_iia_method():
    c, T, TI = radau.RADAU_C, radau.RADAU_T, radau.RADAU_TI
    lam = np.diag([radau.RADAU_GAMMA, radau.RADAU_ALPHA, radau.RADAU_ALPHA])
    lam[1, 2], lam[2, 1] = radau.RADAU_BETA, -radau.RADAU_BETA
    a = np.linalg.inv(T @ lam @ TI)
    np.testing.assert_allclose(a.sum(axis=1), c, atol=1e-14)          # row sums are the nodes
    np.testing.assert_allclose(a[2] @ c ** 2, 1 / 3, atol=1e-14)       # weights b = last row
    assert radau.RADAU_GAMMA == pytest.approx(3 + 3 ** (2 / 3) - 3 ** (1 / 3), rel=1e-13)
    s6 = np.sqrt(6)
    np.testing.assert_allclose(radau.RADAU_E, [(-13 - 7 * s6) / 3, (-13 + 7 * s6) / 3, -1 / 3],
                               rtol=1e-12)
    # The dense-output polynomial reproduces the stage increments at the nodes.
    powers = np.column_stack([c, c ** 2, c ** 3])
    np.testing.assert_allclose(powers @ radau.RADAU_P, np.eye(3), atol=1e-12)


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
