"""Cost per right-hand-side evaluation against SciPy with a lambdified function (measured only).

Run with ``pytest tests/numerics/test_performance.py -m slow -s``; nothing is asserted but the
results' agreement.
"""

from __future__ import annotations

import time

import numpy as np
import pytest
import sympy as sp
from numba import njit
from scipy.integrate import solve_ivp

from flexkane.numerics import integrate


@pytest.mark.slow
def test_report_cost_per_evaluation_double_pendulum(double_pendulum_eom, double_pendulum_module):
    eom, module = double_pendulum_eom, double_pendulum_module
    p = np.array([1.0, 1.5, 1.0, 0.7, 9.81])
    y0 = np.array([1.0, 2.0, 0.0, 0.0])
    t = np.linspace(0.0, 20.0, 2001)
    rhs = module.rhs

    @njit
    def many_calls(count, y, p, dy):
        for _ in range(count):
            rhs(0.0, y, p, dy)

    dy = np.empty(4)
    many_calls(1, y0, p, dy)
    count = 1_000_000
    tic = time.perf_counter()
    many_calls(count, y0, p, dy)
    per_rhs = (time.perf_counter() - tic) / count

    integrate(module, y0, t, p, rtol=1e-9, atol=1e-9, method="dop853")  # compile
    ours = integrate(module, y0, t, p, rtol=1e-9, atol=1e-9, method="dop853")

    args = [eom.t, *eom.q, *eom.u, *eom.constants]
    mass = sp.lambdify(args, eom.mass_matrix, "numpy", cse=True)
    forcing = sp.lambdify(args, eom.forcing, "numpy", cse=True)

    def fun(time_, y):
        u_dot = np.linalg.solve(mass(time_, *y, *p), forcing(time_, *y, *p)).ravel()
        return np.concatenate([y[2:], u_dot])

    tic = time.perf_counter()
    for _ in range(2000):
        fun(0.0, y0)
    per_lambdify = (time.perf_counter() - tic) / 2000
    tic = time.perf_counter()
    ref = solve_ivp(fun, (0.0, 20.0), y0, method="DOP853", rtol=1e-9, atol=1e-9, t_eval=t)
    scipy_wall = time.perf_counter() - tic
    np.testing.assert_allclose(ours.y[:200], ref.y.T[:200], atol=1e-5)
    print(f"\nrhs (Numba, in a compiled loop): {per_rhs * 1e9:.0f} ns per evaluation"
          f"\nflexkane dop853: {ours.wall_time * 1e3:.1f} ms for {ours.nfev} evaluations "
          f"({ours.wall_time / ours.nfev * 1e9:.0f} ns per evaluation, loop included)"
          f"\nlambdify + numpy.linalg.solve: {per_lambdify * 1e6:.1f} us per evaluation"
          f"\nsolve_ivp DOP853 + lambdify: {scipy_wall * 1e3:.0f} ms for {ref.nfev} evaluations "
          f"({scipy_wall / ref.nfev * 1e6:.1f} us per evaluation)"
          f"\nspeed-up of the whole integration: {scipy_wall / ours.wall_time:.0f}x")
