"""simulate(..., controller=f): a control law in the loop, in Python or compiled with Numba.

Physics oracle: a P controller on a free hub carrying a clamped beam, effort = -Kp (q - q_ref), is the
same system as a torsional spring of stiffness Kp relaxed at q_ref; with feedback the actuator's power
is the rate of kinetic plus strain energy (the energy balance E - E0 - W stays at the solver's error).
"""

import numpy as np
import pytest
from control_models import KP, Q_REF, hub_beam
from numba import njit

import flexkane
from flexkane import ModelError

RUN = dict(t_end=0.6, dt_out=0.01, rtol=1e-12, atol=1e-14, method="dop853")


@pytest.fixture(scope="module")
def free_hub():
    return flexkane.compile_model(flexkane.derive(hub_beam(spring=False)))


@pytest.fixture(scope="module")
def spring_run():
    return flexkane.simulate(flexkane.compile_model(flexkane.derive(hub_beam(spring=True))), **RUN)


def p_law(t, y):
    return [-KP * (y[0] - Q_REF)]


@njit
def p_law_compiled(t, y):
    return np.array([-KP * (y[0] - Q_REF)])


def test_p_controller_on_a_free_hub_is_a_torsional_spring(free_hub, spring_run):
    controlled = flexkane.simulate(free_hub, controller=p_law, **RUN)
    assert controlled.state_names == spring_run.state_names
    np.testing.assert_allclose(controlled.state, spring_run.state, rtol=0, atol=1e-10)
    np.testing.assert_allclose(controlled["tip_link"], spring_run["tip_link"], rtol=0, atol=1e-10)
    np.testing.assert_allclose(controlled["input_effort_hub"], -KP * (controlled["q_hub"] - Q_REF), rtol=1e-14)
    # actuator power = d(kinetic + strain)/dt: the balance is the solver's error only
    energy = controlled["energy"]
    assert np.abs(controlled["energy_balance"]).max() < 1e-9 * np.abs(energy).max()
    assert np.ptp(controlled["work"]) > 1e-3 * np.abs(energy).max()   # the controller does work


def test_numba_controller_gives_the_python_controllers_numbers(free_hub):
    python = flexkane.simulate(free_hub, controller=p_law, **RUN)
    compiled = flexkane.simulate(free_hub, controller=p_law_compiled, **RUN)
    np.testing.assert_array_equal(compiled.state, python.state)


def test_controlled_runs_are_reproducible_and_a_zero_controller_changes_nothing(free_hub):
    first = flexkane.simulate(free_hub, controller=lambda t, y: {"input_effort_hub": -KP * (y[0] - Q_REF)}, **RUN)
    again = flexkane.simulate(free_hub, controller=p_law, **RUN)
    np.testing.assert_array_equal(first.state, again.state)           # a dict by name = the array
    plain = flexkane.simulate(free_hub, **RUN)
    zero = flexkane.simulate(free_hub, controller=lambda t, y: np.zeros(1), **RUN)
    np.testing.assert_allclose(zero.state, plain.state, rtol=0, atol=1e-12)
    assert "input_effort_hub" not in plain.outputs


@pytest.mark.parametrize("law, match", [
    (lambda t, y: [1.0, 2.0], r"1 efforts \(input_effort_hub\).*shape \(2,\)"),
    (lambda t, y: [np.nan], "finite efforts"),
    (lambda t, y: [1.0] if t < 0.1 else [np.inf], r"finite efforts.*input_effort_hub = inf at t = 0\.1"),
    (lambda t, y: {"input_effort_elbow": 1.0}, "input channels"),
    (lambda t, y: "torque", "1 efforts"),
])
def test_bad_controller_output_is_a_clear_error(free_hub, law, match):
    with pytest.raises(ModelError, match=match) as info:
        flexkane.simulate(free_hub, controller=law, **RUN)
    assert info.value.path == "controller"


def test_compiled_controller_with_a_bad_output_is_a_clear_error(free_hub):
    @njit
    def two(t, y):
        return np.ones(2)

    @njit
    def diverging(t, y):
        return np.array([1.0 if t < 0.1 else np.nan])

    with pytest.raises(ModelError, match="1 efforts"):
        flexkane.simulate(free_hub, controller=two, **RUN)
    with pytest.raises(ModelError, match=r"1 finite efforts .*near t = 0\.1"):
        flexkane.simulate(free_hub, controller=diverging, **RUN)


def test_an_exception_of_the_controller_reaches_the_caller(free_hub):
    def failing(t, y):
        if t > 0.05:
            raise ZeroDivisionError("the policy failed")
        return [0.0]

    with pytest.raises(ZeroDivisionError, match="the policy failed"):
        flexkane.simulate(free_hub, controller=failing, **RUN)


def test_a_model_without_inputs_refuses_a_controller():
    compiled = flexkane.compile_model(flexkane.derive(flexkane.builtin_model("spin-up-linear").with_modes(1)))
    with pytest.raises(ModelError, match="control inputs"):
        flexkane.simulate(compiled, controller=lambda t, y: [], t_end=0.01)


def test_controlled_results_write_and_load_with_their_input_columns(free_hub, tmp_path):
    results = flexkane.simulate(free_hub, controller=p_law_compiled, t_end=0.05, dt_out=0.01)
    results.write(tmp_path)
    loaded = flexkane.load_results(tmp_path / "results.npz")
    np.testing.assert_array_equal(loaded["input_effort_hub"], results["input_effort_hub"])
    np.testing.assert_array_equal(loaded.state, results.state)


@pytest.fixture(scope="module")
def pid_arm():
    return flexkane.builtin_model("flexible-arm-pid")


def test_controller_sees_the_controller_states_and_can_cancel_a_disturbance(pid_arm):
    """flexible-arm-pid: the law gets y = [q, u, z] (its integral state last) at every evaluation and
    output row; adding +tau_d through the disturbance's input cancels the load, so the PID's integral
    settles at 0 instead of tau_d / Ki (which it reaches with the input at 0)."""
    tau_d, ki = pid_arm.parameters["tau_d"], pid_arm.parameters["Ki"]
    compiled = flexkane.compile_model(flexkane.derive(pid_arm))
    names = compiled.derivation.manifest["state_names"]
    assert names[-1] == "error_integral"
    sizes = set()

    def cancel(t, y):
        sizes.add(len(y))
        return {"input_load_disturbance_torque": tau_d}

    run = dict(t_end=16.0, dt_out=0.5, rtol=1e-8, atol=1e-10)
    cancelled = flexkane.simulate(compiled, controller=cancel, **run)
    assert sizes == {len(names)}
    np.testing.assert_allclose(cancelled["input_load_disturbance_torque"], tau_d)
    assert abs(cancelled["error_integral"][-1]) < 1e-3 * tau_d / ki
    held = flexkane.simulate(compiled, controller=lambda t, y: {"input_load_disturbance_torque": 0.0}, **run)
    assert held["error_integral"][-1] == pytest.approx(tau_d / ki, rel=1e-3)
