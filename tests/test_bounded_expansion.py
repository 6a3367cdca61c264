"""Symbolic work on user expressions is bounded: user time laws are never expanded, the size of
an expansion is estimated before it is done, and combined exponents are limited."""

import pytest
import sympy as sp

from flexkane.errors import ModelError
from flexkane.expressions import (MAX_EXPANDED_TERMS, bounded_expand, expansion_terms,
                                  parse_expression, time_derivative)

t = sp.Symbol("t", real=True)
q, ud = sp.symbols("q ud", real=True)


def test_the_expansion_estimate_counts_multinomial_terms_without_expanding():
    x, y, z = sp.symbols("x y z")
    assert expansion_terms((x + y) ** 2) == 3           # x^2 + 2xy + y^2: C(2 + 2 - 1, 2)
    assert expansion_terms((x + y + z) ** 3) == 10      # C(5, 3)
    assert expansion_terms((x + y) * (y + z)) == 4
    huge = parse_expression("(t + sin(t) + cos(t) + exp(t) + t**2 + 1)**100", {"t": t}, path="torque")
    assert expansion_terms(huge) == MAX_EXPANDED_TERMS + 1     # capped, computed at once


def test_a_user_power_stays_whole_while_the_equation_is_expanded():
    torque = parse_expression("(t + sin(t) + cos(t) + exp(t) + t**2 + 1)**100", {"t": t}, path="torque")
    expr = (q + 1) ** 2 * torque * ud + q * ud
    expanded = bounded_expand(expr, [q, ud], t)
    assert sp.expand(expanded - (q ** 2 * torque * ud + 2 * q * torque * ud + torque * ud + q * ud),
                     multinomial=False, power_base=False) == 0
    assert expanded.count(torque) == 3     # the torque appears whole, never multiplied out


def test_an_expansion_beyond_the_limit_is_declined():
    a = sp.symbols("a0:12")
    expr = sp.Mul(*[(q + s) for s in a]) * ud    # 2**12 = 4096 terms expanded
    assert bounded_expand(expr, [q, ud, *a], t) is None
    assert bounded_expand(expr, [q, ud, *a], t, limit=5000) is not None


def test_powers_of_powers_are_limited_by_their_combined_exponent():
    with pytest.raises(ModelError) as info:
        parse_expression("((t + 1)**20)**20", {"t": t}, path="joints.j.torque")
    assert "combined exponent 400 above 100" in str(info.value)
    assert parse_expression("((t + 1)**10)**10", {"t": t}, path="x") == (t + 1) ** 100


@pytest.mark.parametrize("text", ["abs(t - 0.005)", "max(t, 1)", "min(2*t, 3, t + 1)",
                                  "where(t < 1, t**2, 2*t - 1)", "piecewise(0, t < 1, abs(t - 2), t < 3, 1)"])
def test_time_derivatives_of_kinked_laws_have_no_impulses(text):
    law = parse_expression(text, {"t": t}, path="joints.j.driver.coordinate")
    for order in (1, 2):
        derivative = time_derivative(law, t, path="joints.j.driver.coordinate", order=order)
        assert not derivative.has(sp.DiracDelta, sp.Heaviside, sp.sign, sp.Derivative)
        for when in (-0.5, 0.25, 1.5, 2.5, 4.0):   # away from kinks it is the ordinary derivative
            exact = sp.diff(law, t, order).subs(t, when)
            assert float(derivative.subs(t, when)) == pytest.approx(float(exact.rewrite(sp.Piecewise)
                                                                             .subs(t, when)), abs=1e-12)


def test_at_a_kink_the_derivative_is_the_one_of_the_branch_that_holds():
    law = parse_expression("abs(t - 1)", {"t": t}, path="x")
    assert time_derivative(law, t, path="x").subs(t, 1) == 1     # the branch t - 1 >= 0
