"""The numbers of derived equations are values computed from (eom, model), not state of the equations.

``flexkane.kane.numeric`` gives the constants, the parameter vector and the initial state of any
model that differs from the derived one by its numbers only; the loop closure is checked against the
four-bar's geometry written out by hand.
"""

import math

import numpy as np
import pytest

import flexkane
from flexkane.kane import numeric


@pytest.fixture(scope="module")
def four_bar():
    model = flexkane.builtin_model("four-bar")
    return model, flexkane.derive(model)


def test_initial_state_of_a_variant_closes_the_loop_by_the_geometry(four_bar):
    model, eom = four_bar
    variant = model.with_values({"initial.q_crank": 0.5, "d": 0.28})
    state = numeric.initial_state(eom, variant)
    q = dict(zip(eom.state_names, state))
    a, b, c, d = 0.1, 0.3, 0.25, 0.28
    crank, coupler, rocker = q["q_crank"], q["q_crank"] + q["q_coupler"], q["q_rocker"]
    coupler_tip = (a * math.cos(crank) + b * math.cos(coupler), a * math.sin(crank) + b * math.sin(coupler))
    rocker_tip = (d + c * math.cos(rocker), c * math.sin(rocker))
    assert q["q_crank"] == 0.5
    assert np.allclose(coupler_tip, rocker_tip, rtol=0, atol=1e-10)
    # the derived equations are not changed by a variant: the derived model's state is as before
    np.testing.assert_array_equal(eom.initial_state(), numeric.initial_state(eom, model))
    assert not np.allclose(eom.initial_state(), state)


def test_parameter_vector_of_a_variant_holds_its_numbers(four_bar):
    model, eom = four_bar
    names = [s.name for s in eom.constants]
    p = numeric.parameter_vector(eom, model.with_values({"m2": 0.75}))
    assert p[names.index("m2")] == 0.75
    assert p[names.index("I2")] == pytest.approx(0.75 * 0.3 ** 2 / 12, rel=1e-15)   # I2 = m2 b^2 / 12
    np.testing.assert_array_equal(eom.parameter_vector(), numeric.parameter_vector(eom, model))
    assert eom.constant_values() == numeric.constant_values(eom, model)


def test_a_dependent_speed_given_initially_is_refused(four_bar):
    model, eom = four_bar
    with pytest.raises(flexkane.ModelError) as info:
        numeric.initial_state(eom, model.with_values({"initial.u_rocker": 1.0}))
    assert info.value.path == "initial.u_rocker"
