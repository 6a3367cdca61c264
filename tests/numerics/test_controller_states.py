"""Controller states in generated code: y = [q, u, z, W], z' written beside q' and u'."""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp

from flexkane.numerics import codegen, generate_rhs_source, large_rhs
from flexkane.numerics.jit_module import build_module, structure_key


def pi_oscillator(models):
    """``m x'' = -k x - c x' - ki z`` with the integral state ``z' = x - r``; the quadrature is the
    power of the integral action, ``W' = -ki z u``."""
    t, x, u, z = sp.symbols("t x u z")
    m, k, c, ki, r = sp.symbols("m k c ki r")
    eom = models.eom(t, [x], [u], [c, k, ki, m, r], [u], [[m]], [-k * x - c * u - ki * z])
    eom.z = [z]
    eom.zdot = sp.Matrix([x - r])
    return eom, -ki * z * u


@pytest.mark.parametrize("split", [False, True])
def test_controller_states_follow_the_speeds_and_precede_the_quadratures(models, monkeypatch, split):
    eom, power = pi_oscillator(models)
    if split:
        monkeypatch.setattr(large_rhs, "SPLIT_CHARS", 10)
        monkeypatch.setattr(codegen, "_has_long_sums", lambda exprs: True)   # its sums are short: split anyway
    source = generate_rhs_source(eom, quadratures={"work": power})
    assert ("def rhs_part0(" in source) == split
    assert "NZ = 1" in source and "STATE_NAMES = ('x', 'u', 'z')" in source
    assert "# State vector y = [q, u, z] (nq = 1 coordinates, nu = 1 speeds, nz = 1 controller states):" in source
    module = build_module(source, structure_key(source))
    c, k, ki, m, r = 0.3, 2.0, 0.7, 1.5, 0.2
    p = np.array([c, k, ki, m, r])
    y = np.array([0.4, -1.1, 0.25, 0.0])
    dy = np.empty(4)
    assert module.system_rhs(0.0, y, p, dy) == 0
    expected = [-1.1, (-k * 0.4 - c * -1.1 - ki * 0.25) / m, 0.4 - r, -ki * 0.25 * -1.1]
    np.testing.assert_allclose(dy, expected, rtol=1e-15)
    assert module.rhs(0.0, y[:3], p, dy[:3]) == 0
    np.testing.assert_allclose(dy[:3], expected[:3], rtol=1e-15)
