"""User-given shape functions: symbolic derivatives, clear errors, admissibility at the clamp."""

import numpy as np
import pytest
import sympy

from flexkane.errors import ModelError
from flexkane.modes import XI, get_family
from flexkane.modes.free_vibration import static_tip_load_coordinates

xi = sympy.Symbol("xi")


def test_values_and_derivatives_come_from_the_expressions():
    family = get_family("expression", expressions=[xi ** 2, sympy.sin(sympy.pi * xi / 2) * xi])
    x = np.linspace(0, 1, 7)
    np.testing.assert_allclose(family.phi(x, 2)[0], x ** 2)
    np.testing.assert_allclose(family.phi(x, 1, 1)[0], 2 * x)
    np.testing.assert_allclose(family.phi(x, 1, 2)[0], 2 + 0 * x)
    np.testing.assert_allclose(family.phi(x, 1, 3)[0], 0 * x)
    d4 = sympy.lambdify(xi, sympy.diff(sympy.sin(sympy.pi * xi / 2) * xi, xi, 4))(x)
    np.testing.assert_allclose(family.phi(x, 2, 4)[1], d4, rtol=1e-14)


def test_a_symbol_named_xi_with_assumptions_is_accepted():
    real_xi = sympy.Symbol("xi", positive=True)
    family = get_family("expression", expressions=[real_xi ** 3])
    assert family.expressions[0] == XI ** 3


def test_cubic_expressions_give_the_exact_static_tip_deflection():
    family = get_family("expression", expressions=[xi ** 2, xi ** 3], boundary="clamped-free")
    q = static_tip_load_coordinates(family, 2, 2.0, 35.3, 3.0)
    assert q @ family.phi(1.0, 2)[:, 0] == pytest.approx(3.0 * 2.0 ** 3 / (3 * 35.3), rel=1e-13)


def test_more_modes_than_expressions_is_an_error():
    family = get_family("expression", expressions=[xi ** 2])
    with pytest.raises(ModelError, match="at most 1"):
        family.phi(0.5, 2)


@pytest.mark.parametrize("expressions, path, message", [
    (["xi**2"], "expressions[0]", "parse_expression"),
    ([xi ** 2, sympy.Symbol("L") * xi], "expressions[1]", "unknown symbol"),
    ([1 / xi], "expressions[0]", "finite"),
    ([sympy.log(xi)], "expressions[0]", "finite"),
    ([], "expressions", "non-empty"),
    (xi ** 2, "expressions", "list"),
    ([lambda x: x], "expressions[0]", "SymPy expression"),
])
def test_bad_expressions_are_reported_with_their_index(expressions, path, message):
    with pytest.raises(ModelError, match=message) as info:
        get_family("expression", expressions=expressions)
    assert info.value.path == path


def test_expressions_vanishing_with_their_slope_at_the_clamp_are_admissible():
    family = get_family("expression", expressions=[xi ** 2, 1 - sympy.cos(xi)],
                        boundary="clamped-free")
    assert family.boundary == "clamped-free"


def test_an_expression_with_a_slope_at_the_clamp_names_the_condition():
    family = get_family("expression", expressions=[xi ** 2, sympy.sin(xi)])
    with pytest.raises(ModelError) as info:
        family.admissibility("clamped-free")
    assert info.value.path == "expressions[1]"
    assert "Phi'(0) = 0" in str(info.value)
    assert "Phi'(0) = 1" in str(info.value)


def test_an_expression_displaced_at_the_clamp_names_the_condition():
    with pytest.raises(ModelError) as info:
        get_family("expression", expressions=[1 + xi ** 2], boundary="clamped")
    assert info.value.path == "expressions[0]"
    assert "Phi(0) = 0" in str(info.value)


def test_admissibility_at_a_pinned_tip_is_checked_too():
    family = get_family("expression", expressions=[xi ** 2 * (1 - xi), xi ** 3])
    with pytest.raises(ModelError, match=r"Phi\(1\) = 0"):
        family.admissibility("clamped-pinned")
    get_family("expression", expressions=[xi ** 2 * (1 - xi)], boundary="clamped-pinned")


def test_unknown_boundary_is_an_error():
    with pytest.raises(ModelError) as info:
        get_family("expression", expressions=[xi ** 2], boundary="glued")
    assert info.value.path == "boundary"
