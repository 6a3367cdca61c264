"""Quadrature states: the work of non-conservative forces integrated with the motion.

A damped oscillator pushed by a force F0 that is switched off at t = 0.5 s (a step):
``m x'' = -k x - c x' + F(t)``. The work ``W`` of damper and force is integrated as an extra state,
so ``E - E0 - W`` is the integration error alone and falls with the tolerance; the trapezoidal rule
on the output grid cannot see the step and stays at its own error whatever the tolerance.
"""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp
from scipy.integrate import cumulative_trapezoid

from flexkane.numerics import build_module, generate_outputs_source, generate_rhs_source, \
    integrate, structure_key
from flexkane.numerics.integrate import compile_integrators, evaluate_outputs


@pytest.fixture(scope="module")
def pushed_oscillator(models):
    t, x, v, vd = sp.symbols("t x v vd")
    m, k, c, F0 = sp.symbols("m k c F0")
    force = sp.Piecewise((F0, t < sp.Rational(1, 2)), (0, True))
    eom = models.eom(t, [x], [v], [F0, c, k, m], [v], [[m]], [-k * x - c * v + force])
    eom.ud = [vd]
    quadratures = {"work": (m * vd + k * x) * v,  # power of all non-conservative forces, via u'
                   "damper": -c * v ** 2}
    source = generate_rhs_source(eom, quadratures=quadratures) \
        + "\n\n" + generate_outputs_source({"energy": m * v ** 2 / 2 + k * x ** 2 / 2}, eom)
    module = build_module(source, structure_key(source))
    compile_integrators(module)
    return module


P = np.array([3.0, 0.3, 40.0, 1.5])  # F0 [N], c [N s/m], k [N/m], m [kg]
T = np.linspace(0.0, 2.0, 201)


def _balance(module, rtol, method="dop853"):
    res = integrate(module, np.array([0.05, 0.0]), T, P, rtol=rtol, atol=1e-12, method=method)
    assert res.success
    energy = evaluate_outputs(module, res.t, res.y, P)["energy"]
    work = res.quadratures[:, 0]
    return res, energy, work, np.abs(energy - energy[0] - work).max() / np.abs(energy).max()


def test_module_declares_its_quadrature_states(pushed_oscillator):
    assert pushed_oscillator.NW == 2
    assert pushed_oscillator.QUADRATURE_NAMES == ("work", "damper")
    res, _, _, _ = _balance(pushed_oscillator, 1e-8)
    assert res.y.shape == (T.size, 2) and res.quadratures.shape == (T.size, 2)
    assert res.quadratures[0].tolist() == [0.0, 0.0]


@pytest.mark.parametrize("method", ["dop853", "radau"])
def test_energy_balance_falls_with_the_tolerance_across_a_switched_off_force(pushed_oscillator,
                                                                              method):
    _, _, _, loose = _balance(pushed_oscillator, 1e-6, method)
    res, energy, work, tight = _balance(pushed_oscillator, 1e-10, method)
    assert tight < 1e-9
    assert loose > 30 * tight
    # the trapezoidal work of the same power on the output grid misses the step by far more
    x, v = res.y[:, 0], res.y[:, 1]
    F0, c, k, m = P
    power = (np.where(T < 0.5, F0, 0.0) - c * v) * v
    trapezoid = cumulative_trapezoid(power, T, initial=0.0)
    assert np.abs(energy - energy[0] - trapezoid).max() / np.abs(energy).max() > 1000 * tight


def test_work_of_the_force_is_force_times_displacement(pushed_oscillator):
    res, _, work, _ = _balance(pushed_oscillator, 1e-11)
    damper = res.quadratures[:, 1]
    assert np.all(np.diff(damper) <= 1e-15)  # a damper only dissipates
    # after the force is off, the work of all forces minus the damper's is F0 (x(0.5) - x(0))
    x_half = np.interp(0.5, res.t, res.y[:, 0])
    force_work = work - damper
    np.testing.assert_allclose(force_work[res.t > 0.5], P[0] * (x_half - res.y[0, 0]), rtol=1e-8)
