"""The compiled DOP853 against SciPy's on the same equations: same answer, comparable work.

Counts, not times: timing belongs to ``benchmarks/simulation.py`` (cost per evaluation, whole
runs against ``solve_ivp`` with ``lambdify``), since a test must not depend on machine load.
"""

from __future__ import annotations

import numpy as np
import sympy as sp
from scipy.integrate import solve_ivp

from flexkane.numerics import integrate


def test_dop853_matches_scipy_dop853_with_comparable_evaluation_count(double_pendulum_eom,
                                                                       double_pendulum_module):
    eom, module = double_pendulum_eom, double_pendulum_module
    p = np.array([1.0, 1.5, 1.0, 0.7, 9.81])
    y0 = np.array([1.0, 2.0, 0.0, 0.0])
    t = np.linspace(0.0, 5.0, 501)
    ours = integrate(module, y0, t, p, rtol=1e-9, atol=1e-9, method="dop853")
    args = [eom.t, *eom.q, *eom.u, *eom.constants]
    mass = sp.lambdify(args, eom.mass_matrix, "numpy", cse=True)
    forcing = sp.lambdify(args, eom.forcing, "numpy", cse=True)

    def fun(time_, y):
        u_dot = np.linalg.solve(mass(time_, *y, *p), forcing(time_, *y, *p)).ravel()
        return np.concatenate([y[2:], u_dot])

    ref = solve_ivp(fun, (0.0, 5.0), y0, method="DOP853", rtol=1e-9, atol=1e-9, t_eval=t)
    assert ours.success and ref.success
    np.testing.assert_allclose(ours.y, ref.y.T, atol=1e-6)
    # the same method and error control: the work differs by the step-size details only
    assert 0.5 < ours.nfev / ref.nfev < 2.0
