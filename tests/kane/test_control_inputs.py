"""Control inputs (flexkane.kane.inputs) enter F_r through the partial velocities, and only when asked.

The oracle for a load's inputs is the model's own load: a force and torque given by parameters
enter F_r exactly as the inputs do, so the Jacobians of the forcing with respect to both agree.
"""

import pytest
import sympy as sp

import flexkane
from flexkane import Model, ModelError
from flexkane.kane import derive
from flexkane.kane.inputs import input_channels, input_symbols, with_control_inputs
from flexkane.model.parts import Beam, Joint, Load, RigidBody


def slider_with_flexible_arm():
    """A cart on a prismatic joint carrying a hinged flexible arm, pushed at a station of the arm."""
    model = Model(name="slider-arm", parameters={"m": 2.0, "J": 0.1, "L": 0.8, "EI": 9.0, "rho": 0.5,
                                                  "Fx": 0.3, "Fy": -0.2, "Tq": 0.1})
    model.bodies["cart"] = RigidBody(name="cart", mass="m", inertia="J")
    model.beams["arm"] = Beam(name="arm", L="L", EI="EI", rho="rho", n_modes=2)
    model.joints["slide"] = Joint(name="slide", type="prismatic", parent="ground", child="cart", axis=0.3)
    model.joints["hinge"] = Joint(name="hinge", type="revolute", parent="cart", child="arm", torque="0.5*t")
    model.loads["push"] = Load(name="push", body="arm", station="0.6", force=("Fx", "Fy"), torque="Tq",
                               frame="local")
    return model.validate()


def test_channels_are_named_ordered_and_have_units():
    channels = input_channels(slider_with_flexible_arm())
    assert [(c.name, c.unit) for c in channels] == [
        ("input_effort_slide", "N"), ("input_effort_hinge", "N m"), ("input_load_push_fx", "N"),
        ("input_load_push_fy", "N"), ("input_load_push_torque", "N m")]
    assert channels[1].path == "joints.hinge.torque" and channels[3].path == "loads.push.force[1]"


def test_driven_joints_have_no_effort_input():
    names = [c.name for c in input_channels(flexkane.builtin_model("spin-up"))]
    assert names == []                       # the hub is driven: its effort is the driver's output


def test_a_parameter_named_like_an_input_is_refused():
    model = slider_with_flexible_arm().with_values({"parameters.input_effort_hinge": 1.0})
    with pytest.raises(ModelError, match="input_effort_hinge"):
        input_channels(model)


def test_without_control_inputs_the_equations_have_none_and_with_zero_inputs_they_are_the_same():
    model = slider_with_flexible_arm()
    plain, with_inputs = derive(model), derive(with_control_inputs(model))
    assert input_symbols(plain.chain) == {}
    symbols = list(input_symbols(with_inputs.chain).values())
    assert len(symbols) == 5 and set(symbols) <= set(with_inputs.constants)
    assert not set(symbols) & set(plain.constants)
    zero = {s: 0 for s in symbols}
    difference = (with_inputs.forcing.xreplace(zero) - plain.forcing).applyfunc(sp.expand)
    assert difference == sp.zeros(*difference.shape)
    assert with_inputs.mass_matrix == plain.mass_matrix


def test_load_inputs_act_like_the_load_itself_and_an_effort_on_its_joint_speed():
    eom = derive(with_control_inputs(slider_with_flexible_arm()))
    symbols = input_symbols(eom.chain)
    params = eom.chain.symbols.parameters
    f = eom.forcing
    by_inputs = f.jacobian([symbols["input_load_push_fx"], symbols["input_load_push_fy"],
                            symbols["input_load_push_torque"]])
    by_load = f.jacobian([params["Fx"], params["Fy"], params["Tq"]])
    assert (by_inputs - by_load).applyfunc(sp.simplify) == sp.zeros(*by_load.shape)
    efforts = f.jacobian([symbols["input_effort_slide"], symbols["input_effort_hinge"]])
    u = [s.name for s in eom.u]
    expected = sp.zeros(len(u), 2)
    expected[u.index("u_slide"), 0] = 1
    expected[u.index("u_hinge"), 1] = 1
    assert efforts == expected
