"""The run manifest's units of controller states and outputs (read from the model's expressions)."""

from flexkane import Model
from flexkane.derivation_cache import derive
from flexkane.model.parts import Controller, Joint, RigidBody, Sensor
from flexkane.run_manifest import units


def _controlled_hub() -> Model:
    """A hub on a revolute joint under a PI law on its angle, a filter state and an unfixed state."""
    model = Model(name="pi-hub", parameters={"J": 0.05, "Kp": 3.0, "Ki": 1.0, "q_ref": 0.2, "c": 1.0, "d": 0.0})
    model.bodies["hub"] = RigidBody(name="hub", mass=1.0, inertia="J")
    model.joints["hub"] = Joint(name="hub", type="revolute", parent="ground", child="hub", torque="motor")
    model.sensors["angle"] = Sensor(name="angle", type="joint_angle", joint="hub")
    model.controllers["error"] = Controller(name="error", output="q_ref - angle")
    model.controllers["motor"] = Controller(
        name="motor", states={"z_int": "error", "z_rate": "(u_hub - z_rate)*c", "z_free": "d"},
        output="Kp*error + Ki*z_int")
    return model.validate()


def test_controller_states_and_outputs_get_the_units_their_expressions_fix():
    eom = derive(_controlled_hub(), cache=False)
    unit = units(eom)
    assert unit["z_int"] == "rad s"             # the integral of an angle error [rad]
    assert unit["z_rate"] == "rad/s"            # filtered like u_hub, with c [1/s] found on the way
    assert unit["controller_error"] == "rad" and unit["controller_motor"] == "N m"   # feeds the torque
    assert "z_free" not in unit                 # its rate d fixes no unit: none is claimed
    assert unit["q_hub"] == "rad" and unit["sensor_angle"] == "rad"
    assert (unit["p_x"], unit["h_o"]) == ("kg m/s", "kg m^2/s")   # the momenta too
