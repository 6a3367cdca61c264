"""Physics of the spatial built-in examples (issue 17 item 6, rigid parts).

* ``spacecraft-slew`` without its slew torque, tumbling about all three axes: the angular momentum
  vector about the mass centre and the kinetic energy stay constant, the mass centre stays at rest
  and the Euler parameters keep unit norm, to the solver's tolerance.
* ``spacecraft-slew`` with its torque: the change of the angular momentum equals the integral of the
  torque (computed independently from the bus's attitude, the torque being in bus axes).
* ``robot-arm-3d``: power balance, the work of the joint torques, springs, dampers and gravity equals
  the change of kinetic energy: ``E - E0 - W`` stays at the solver's tolerance.
"""

from __future__ import annotations

import numpy as np
import pytest

import flexkane
from flexkane.model.orientation import quaternion_matrix


@pytest.fixture(scope="module")
def spacecraft():
    return flexkane.compile_model(flexkane.derive(flexkane.builtin_model("spacecraft-slew")))


def _tumbling(T0: float):
    model = flexkane.builtin_model("spacecraft-slew")
    model.parameters["T0"] = T0
    model.initial.update({"u_float_wx": 0.05, "u_float_wy": -0.03, "u_float_wz": 0.2,
                          "u_float_vx": 0.01, "u_float_vy": 0.0, "u_float_vz": -0.02})
    return model


def test_torque_free_spacecraft_conserves_momenta(spacecraft):
    model = _tumbling(0.0)
    results = flexkane.simulate(spacecraft, model=model, t_end=20.0, dt_out=0.5, rtol=1e-11, atol=1e-13)
    H = np.column_stack([results["H_x"], results["H_y"], results["H_z"]])
    assert np.linalg.norm(H[0]) > 1.0
    assert np.max(np.abs(H - H[0])) < 1e-8 * np.linalg.norm(H[0])
    kinetic = results["kinetic"]
    assert np.max(np.abs(kinetic - kinetic[0])) < 1e-8 * kinetic[0]
    p = np.column_stack([results["p_x"], results["p_y"], results["p_z"]])
    assert np.max(np.abs(p - p[0])) < 1e-9 * np.max(np.abs(p[0]))
    assert np.max(np.abs(results["quaternion_norm_float"])) < 1e-9
    # the mass centre moves uniformly: its position is linear in t
    for axis in "xyz":
        x = results[f"{axis}_cm"]
        fit = np.polyval(np.polyfit(results.t, x, 1), results.t)
        assert np.max(np.abs(x - fit)) < 1e-8


def test_slew_changes_angular_momentum_by_the_torque_impulse(spacecraft):
    model = flexkane.builtin_model("spacecraft-slew")
    results = flexkane.simulate(spacecraft, model=model, t_end=12.0, dt_out=0.01, rtol=1e-11, atol=1e-13)
    t = results.t
    T0, t1 = model.parameters["T0"], model.parameters["t1"]
    # the torque along the bus's z axis, turned into ground axes by the bus's Euler parameters
    torque = np.array([quaternion_matrix([results[f"e{k}_bus"][i] for k in range(4)]) @ [0.0, 0.0, 1.0]
                       for i in range(len(t))]) * np.where(t < t1, T0 * np.sin(2 * np.pi * t / t1), 0.0)[:, None]
    # trapezoidal impulse on the 0.01 s grid (the torque is smooth; its error is O(dt^2))
    impulse = np.sum(0.5 * (torque[1:] + torque[:-1]) * np.diff(t)[:, None], axis=0)
    H = np.array([results[f"H_{a}"][-1] - results[f"H_{a}"][0] for a in "xyz"])
    assert np.max(np.abs(H - impulse)) < 1e-6 * T0 * t1    # measured 3e-9 T0 t1
    assert results["yaw_bus"][-1] == pytest.approx(np.pi / 2, abs=0.05)    # a 90 degree slew


def test_robot_arm_power_balance():
    model = flexkane.builtin_model("robot-arm-3d")
    compiled = flexkane.compile_model(flexkane.derive(model))
    results = flexkane.simulate(compiled, model=model, t_end=2.0, dt_out=0.01, rtol=1e-10, atol=1e-12)
    energy = results["energy"]
    assert np.max(np.abs(results["work"])) > 1.0          # the torques do work
    balance = results["energy"] - energy[0] - results["work"]
    assert np.max(np.abs(balance)) < 1e-8 * np.max(np.abs(results["kinetic"]) + np.abs(energy))
    assert np.max(np.abs(results["energy_balance"] - balance)) < 1e-9
