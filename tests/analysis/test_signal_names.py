"""One name per signal: the inputs of a linear model never share a name with its outputs or states.

flexible-arm-pd has a torque law of sensors on its hub: its linear model has the input channel added to
that torque (``input_effort_shoulder``) and the torque the law gives as an output (``effort_shoulder``),
beside the sensors. python-control connects signals by name, so the names must be distinct: a feedback
built by ``interconnect`` from the names alone closes the loop exactly as ``A + B k C`` does.
"""

import numpy as np
import pytest

import flexkane
from flexkane.kane.inputs import INPUT_PREFIX
from flexkane.analysis import linearize

control = pytest.importorskip("control")


@pytest.fixture(scope="module")
def pd_arm():
    return linearize(flexkane.builtin_model("flexible-arm-pd"))


def test_inputs_outputs_and_states_have_distinct_names(pd_arm):
    assert pd_arm.input_names == ["input_effort_shoulder"]
    assert {"effort_shoulder", "sensor_tip", "sensor_root_strain", "sensor_hub_angle"} <= set(pd_arm.output_names)
    names = pd_arm.state_names + pd_arm.input_names + pd_arm.output_names
    assert len(names) == len(set(names))
    assert all(name.startswith(INPUT_PREFIX) for name in pd_arm.input_names)
    assert not any(name.startswith(INPUT_PREFIX) for name in pd_arm.output_names + pd_arm.state_names)


def test_feedback_connected_by_name_in_python_control_is_a_plus_b_k_c(pd_arm):
    plant = pd_arm.to_control()
    assert plant.input_labels == ["input_effort_shoulder"] and "effort_shoulder" in plant.output_labels
    k = -30.0      # strain feedback [N m per unit strain] on the hub torque
    gain = control.ss([], [], [], [[k]], inputs=["sensor_root_strain"], outputs=["input_effort_shoulder"],
                      name="strain_feedback")
    loop = control.interconnect([plant, gain], inputs=[], outputs=["tip_link", "effort_shoulder"], check_unused=False)
    A, B = pd_arm.state_space()
    C, D = pd_arm.output_matrices()
    strain = pd_arm.output_names.index("sensor_root_strain")
    assert not D[strain].any()
    np.testing.assert_allclose(loop.A, A + k * B @ C[[strain]], rtol=0, atol=1e-12 * np.abs(A).max())
    torque = pd_arm.output_names.index("effort_shoulder")
    # the law's torque (an output) does not contain the input added to it: no direct feedthrough
    np.testing.assert_array_equal(D[torque], [0.0])
    np.testing.assert_allclose(loop.C[1], C[torque], rtol=0, atol=1e-12 * np.abs(C[torque]).max())
