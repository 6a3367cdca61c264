"""Every column of the results has a name of its own (issue 25, item 5): a controller state, a
coordinate or speed name, or a body, beam, joint, load or sensor name that would give a column the
name of another (``energy``, ``x_cm``, ``yaw_<body>``, ``work``, ...) is refused with the field named,
and where the results are assembled a name made twice is an internal error, never an overwrite."""

import pathlib

import numpy as np
import pytest

import flexkane
from flexkane.builtin import builtin_names
from flexkane.errors import ModelError, ResultsError
from flexkane.kane.equations import derive
from flexkane.model import columns
from flexkane.model.columns import DuplicateColumnError, Output, Outputs, result_columns
from flexkane.model.coordinates import coordinate_names
from flexkane.results import Results

from spatial_control_models import ATTITUDE, ATTITUDE_LAW, ATTITUDE_PI, HINGE, INTEGRAL, PID

EXAMPLES = pathlib.Path(flexkane.__file__).parent / "builtin_models"
PID_ARM = (EXAMPLES / "flexible-arm-pid.toml").read_text("utf-8")
HINGE_PID = HINGE.replace("{effort}", PID)

#: A planar pendulum whose names the cases below change.
PENDULUM = """
name = "pendulum"
[bodies.bob]
mass = 1.0
inertia = 0.1
points = { pin = [-0.5, 0] }
[joints.pin]
type = "revolute"
parent = "ground"
child = "bob"
child_point = "pin"
{joint}
[gravity]
g = 9.81
direction = [0, -1]
"""

#: (model text, the field refused, texts the message must hold).
HOSTILE = {
    "controller state named energy": (
        PID_ARM.replace("error_integral", "energy"), "controllers.motor.states.energy",
        ["'energy' is the total energy", "got 'energy'"]),
    "controller state named work": (
        PID_ARM.replace("error_integral", "work"), "controllers.motor.states.work",
        ["'work' is the work of the non-conservative forces"]),
    "controller state named after a body's column": (
        PID_ARM.replace("error_integral", "x_payload"), "controllers.motor.states.x_payload",
        ["'x_payload' is a column of body 'payload' (from bodies.payload)"]),
    "coordinate named kinetic": (
        PENDULUM.replace("{joint}", 'coordinates = ["kinetic"]'), "joints.pin.coordinates[0]",
        ["'kinetic' is the kinetic energy", "got 'kinetic'"]),
    "speed named x_cm": (
        PENDULUM.replace("{joint}", 'speeds = ["x_cm"]'), "joints.pin.speeds[0]",
        ["'x_cm' is x of the system's mass centre"]),
    "speed named after the body's angle": (
        PENDULUM.replace("{joint}", 'speeds = ["theta_bob"]'), "joints.pin.speeds[0]",
        ["'theta_bob' is a column of body 'bob'"]),
    "body named cm": (
        PENDULUM.replace("{joint}", "").replace("bodies.bob", "bodies.cm").replace('"bob"', '"cm"'), "bodies.cm",
        ["result columns (x_cm, y_cm, theta_cm)", "'x_cm' is x of the system's mass centre", "got 'cm'"]),
    "3D controller state named yaw of the body": (
        HINGE_PID.replace("zf", "yaw_arm"), "controllers.filter.states.yaw_arm",
        ["'yaw_arm' is a column of body 'arm' (from bodies.arm)"]),
    "3D controller state named after a sensor's column": (
        HINGE_PID.replace("zi", "sensor_tool_z"), "controllers.pid.states.sensor_tool_z",
        ["'sensor_tool_z' is the column of sensor 'tool_z'"]),
    "3D body named cm": (
        ATTITUDE.replace("{torque}", ATTITUDE_LAW).replace("bus", "cm"), "bodies.cm",
        ["'x_cm' is x of the system's mass centre", "got 'cm'"]),
    "3D coordinate named H_x": (
        HINGE.replace("{effort}", 'coordinates = ["H_x"]').replace("q_hinge = 0.1", ""), "joints.hinge.coordinates[0]",
        ["'H_x' is the system's angular momentum about its mass centre along x"]),
    "3D controller state named after a joint's quaternion norm": (
        ATTITUDE.replace("{torque}", ATTITUDE_PI.replace("zx", "quaternion_norm_float"))
        + INTEGRAL.replace("zx", "quaternion_norm_float"), "controllers.integral.states.quaternion_norm_float",
        ["'quaternion_norm_float' is a column of joint 'float' (from joints.float)"]),
}


@pytest.mark.parametrize("case", sorted(HOSTILE))
def test_a_name_that_would_replace_a_column_is_refused_naming_the_field(case):
    text, path, says = HOSTILE[case]
    with pytest.raises(ModelError) as info:
        flexkane.loads_model(text)
    message = str(info.value)
    if path is not None:
        assert info.value.path == path, message
    assert "not already" in message and "column" in message
    missing = [s for s in says if s not in message]
    assert not missing, f"{missing} not in: {message}"


def _columns_made(model) -> tuple[set, set]:
    """The columns the validation names for ``model`` and those its derived equations make."""
    declared = set(result_columns(model, coordinate_names(model)))
    eom = derive(model)
    return declared, {"t", "work", "energy_balance", *eom.state_names, *eom.output_names}


def _loop_model() -> flexkane.Model:
    path = pathlib.Path(__file__).parents[1] / "kane" / "spatial_loops" / "axis_pendulum.toml"
    return flexkane.load_model(path)


@pytest.mark.parametrize("name", ["flexible-arm-pid", "four-bar", "slider-crank", "falling-beam", "pendulum-beam"])
def test_the_columns_named_by_the_validation_are_those_a_planar_model_makes(name):
    declared, made = _columns_made(flexkane.builtin_model(name))
    assert declared == made


@pytest.mark.parametrize("text", [HINGE_PID, ATTITUDE.replace("{torque}", ATTITUDE_LAW)], ids=["hinge-pid", "attitude"])
def test_the_columns_named_by_the_validation_are_those_a_spatial_model_makes(text):
    declared, made = _columns_made(flexkane.loads_model(text))
    assert declared == made


def test_the_columns_named_by_the_validation_are_those_a_spatial_loop_makes():
    declared, made = _columns_made(_loop_model())
    assert declared == made and {"constraint_line_1", "constraint_line_2"} <= made


@pytest.mark.slow
@pytest.mark.parametrize("name", builtin_names())
def test_the_columns_named_by_the_validation_are_those_every_built_in_model_makes(name):
    declared, made = _columns_made(flexkane.builtin_model(name))
    assert declared == made


def test_outputs_made_twice_are_an_internal_error_not_an_overwrite(monkeypatch):
    """With the validation's check bypassed, the body ``cm`` reaches the outputs: the second
    ``x_cm`` stops the derivation instead of replacing the first."""
    text, _, _ = HOSTILE["body named cm"]
    monkeypatch.setattr(columns, "result_columns", lambda model, coordinates: {})
    model = flexkane.loads_model(text)
    with pytest.raises(DuplicateColumnError, match="'x_cm' was made twice"):
        derive(model)


def test_an_output_collection_adds_each_name_once_and_replaces_only_on_purpose():
    table = Outputs([Output("a", 1, "m", "tip", "deflection of a")])
    with pytest.raises(DuplicateColumnError, match=r"'a' was made twice, as deflection of a \[m\] and as the "
                                                    r"total energy \[J\]"):
        table.add("a", 2, "J", "energy", "the total energy")
    table.replace("a", 4)
    with pytest.raises(DuplicateColumnError):
        table.replace("c", 1)
    assert dict(table) == {"a": 4} and table.output("a").unit == "m" and table.output("a").group == "tip"


def test_results_with_a_state_and_an_output_of_one_name_are_refused(tmp_path):
    t = np.array([0.0, 1.0])
    with pytest.raises(DuplicateColumnError, match="energy"):
        Results(t=t, state=np.zeros((2, 1)), state_names=["energy"], outputs={"energy": np.zeros(2)})
    # a file written with such columns (by hand, or by an older version) is refused on reading
    good = Results(t=t, state=np.zeros((2, 1)), state_names=["q"], outputs={"energy": np.zeros(2)})
    good.write(tmp_path)
    with np.load(tmp_path / "results.npz") as data:
        arrays = {k: data[k] for k in data.files}
    arrays["state_names"] = np.array(["energy"])
    np.savez(tmp_path / "results.npz", **arrays)
    with pytest.raises(ResultsError, match="several columns alike"):
        flexkane.load_results(tmp_path)
