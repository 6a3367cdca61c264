"""Linear models of spatial chains for control design: named inputs, outputs and states through the
reduction of Euler parameters to rotation coordinates.

Physics is the oracle: a PD law on a skew revolute joint linearizes as its spring and damper; the
closed loop of an attitude law written in Euler parameters (T = -Kp e_vec - Kd w on a free body) is
``A - B K`` of the open loop with ``K = [Kp/2, Kd]`` on the rotation coordinates (``e_vec = dtheta/2``)
and its eigenvalues are the roots of ``I_i s^2 + Kd s + Kp/2``; an integral state settles where it
holds the weight; the static gains of a clamped beam's sensors from its load inputs are the
cantilever's ``F L^3/(3 EI)``, ``F L^2/(2 EI)``, ``F (L - x)``, ``T L/GJ`` in each plane (shape
functions that hold the static solution exactly).
"""

from __future__ import annotations

import numpy as np
import pytest
from spatial_control_models import (ATTITUDE_LAW, AXIS, BEAM_L, DISTANCE, EI_Y, EI_Z, GJ, INERTIA, KD_ATT, KI,
                                    KP_ATT, MASS, NO_TORQUE, PD_LAW, PID, Q_REF, SENSED_BEAM, SPRING, TOP,
                                    STATION, Evaluated, G, attitude, hinge, random_states)

import flexkane
from flexkane.analysis import Linearization
from flexkane.model import loads_model


@pytest.fixture(scope="module")
def attitude_models():
    closed = Linearization(attitude(ATTITUDE_LAW), about="rest").at()
    opened = Linearization(attitude(NO_TORQUE), about="rest").at()
    return closed, opened


def test_pd_law_linearizes_as_its_spring_and_damper():
    law = Linearization(hinge(PD_LAW)).at()
    spring = Linearization(hinge(SPRING)).at()
    assert law.input_names == spring.input_names == ["input_effort_hinge"]
    (A1, B1), (A2, B2) = law.state_space(), spring.state_space()
    np.testing.assert_allclose(law.q0, spring.q0, rtol=1e-12)
    np.testing.assert_allclose(A1, A2, rtol=1e-12, atol=1e-12 * np.abs(A2).max())
    np.testing.assert_allclose(B1, B2, rtol=1e-12)


def test_closed_loop_is_the_open_loop_minus_b_k(attitude_models):
    """Inputs (torque components in body axes), states (rx, ry, rz of the Euler parameters) and the law
    go through the same reduction: A_closed = A_open - B K to 1e-12."""
    closed, opened = attitude_models
    assert opened.input_names == closed.input_names == [f"input_load_attitude_t{c}" for c in "xyz"]
    assert opened.state_names == closed.state_names
    names = opened.state_names
    assert names[:6] == ["q_float_x", "q_float_y", "q_float_z", "rx_float", "ry_float", "rz_float"]
    A_open, B = opened.state_space()
    A_closed, B_closed = closed.state_space()
    K = np.zeros((3, len(names)))
    for k, c in enumerate("xyz"):
        K[k, names.index(f"r{c}_float")] = KP_ATT / 2      # e_vec = dtheta / 2 about the identity
        K[k, names.index(f"u_float_w{c}")] = KD_ATT
    np.testing.assert_allclose(A_closed, A_open - B @ K, rtol=0, atol=1e-12 * np.abs(A_closed).max())
    np.testing.assert_allclose(B_closed, B, rtol=1e-12)
    # the law's output columns are outputs of the closed loop: dT = -K dx
    C, D = closed.output_matrices()
    rows = [closed.output_names.index(f"load_attitude_t{c}") for c in "xyz"]
    np.testing.assert_allclose(C[rows], -K, rtol=0, atol=1e-12)


def test_attitude_eigenvalues_are_the_closed_form_ones(attitude_models):
    """Each body axis: I_i s^2 + Kd s + Kp/2 = 0; the translations are free (six zero eigenvalues)."""
    closed, _ = attitude_models
    A, _ = closed.state_space()
    found = np.sort_complex(np.linalg.eigvals(A))
    expected = np.sort_complex(np.concatenate([np.roots([I, KD_ATT, KP_ATT / 2]) for I in INERTIA] + [np.zeros(6)]))
    np.testing.assert_allclose(found, expected, rtol=0, atol=1e-12)
    assert np.all(found.real < 1e-12)


def test_integral_state_settles_where_it_holds_the_weight():
    """PID on the skew hinge: at the equilibrium q = q_ref and Ki z = -(gravity torque about the axis);
    the filter state equals the sensor it filters; the state is (q, u, zi, zf). (Without its
    saturation, which the operating point does not reach: SymPy prints the Jacobians of Min and
    Max slowly.)"""
    linear = Linearization(hinge(PID.replace("min = -40\nmax = 40\n", ""))).at()
    assert linear.state_names == ["q_hinge", "u_hinge", "zi", "zf"]
    assert linear.q0[0] == pytest.approx(Q_REF, abs=1e-12)
    c, s = np.cos(Q_REF), np.sin(Q_REF)
    k = np.array([[0, -AXIS[2], AXIS[1]], [AXIS[2], 0, -AXIS[0]], [-AXIS[1], AXIS[0], 0]])
    r_cm = (np.eye(3) + s * k + (1 - c) * k @ k) @ (-TOP)        # mass centre from the pivot
    weight_torque = AXIS @ np.cross(r_cm, [0.0, 0.0, -MASS * G])
    assert linear.z0[0] == pytest.approx(-weight_torque / KI, rel=1e-10)
    assert linear.z0[1] == pytest.approx(linear.y0[linear.output_names.index("sensor_tool_z")], rel=1e-10)
    A, _ = linear.state_space()
    assert np.all(np.linalg.eigvals(A).real < 0)       # the PID holds it


def test_static_gains_of_beam_sensors_are_the_cantilever_formulas():
    linear = Linearization(loads_model(SENSED_BEAM), about="rest").at()
    assert linear.input_names == [f"input_load_tip_{k}" for k in ("fx", "fy", "fz", "tx", "ty", "tz")]
    A, B = linear.state_space()
    C, D = linear.output_matrices()
    gain = -C @ np.linalg.solve(A, B) + D            # static response to each input
    out, into = linear.output_names.index, linear.input_names.index
    L, x = BEAM_L, STATION

    def g(sensor, channel):
        return gain[out(f"sensor_{sensor}"), into(f"input_load_tip_{channel}")]

    expected = {("tip_v", "fy"): L ** 3 / (3 * EI_Z), ("slope_v", "fy"): L ** 2 / (2 * EI_Z),
                ("moment_z", "fy"): L, ("strain_v", "fy"): -DISTANCE * (L - x) / EI_Z,
                ("tip_y", "fy"): L ** 3 / (3 * EI_Z),
                ("tip_w", "fz"): L ** 3 / (3 * EI_Y), ("slope_w", "fz"): L ** 2 / (2 * EI_Y),
                ("moment_y", "fz"): L - x, ("twist_tip", "tx"): L / GJ}
    for (sensor, channel), value in expected.items():
        assert g(sensor, channel) == pytest.approx(value, rel=1e-10), (sensor, channel)
    for sensor in ("tip_v", "slope_v", "moment_z", "strain_v"):      # the planes do not couple
        assert abs(g(sensor, "fz")) < 1e-12 and abs(g(sensor, "tx")) < 1e-12
    for sensor in ("tip_w", "slope_w", "moment_y"):
        assert abs(g(sensor, "fy")) < 1e-12 and abs(g(sensor, "tx")) < 1e-12


def test_to_control_has_the_names_of_the_spatial_linear_model(attitude_models, tmp_path):
    pytest.importorskip("control")
    from flexkane.analysis.linear_model import load_control

    closed, _ = attitude_models
    system = closed.to_control()
    assert list(system.input_labels) == closed.input_names
    assert list(system.state_labels) == closed.state_names
    assert "load_attitude_tx" in system.output_labels and "rx_float" in system.state_labels
    closed.save_control(tmp_path / "statespace.npz")
    again = load_control(tmp_path / "statespace.npz")
    np.testing.assert_array_equal(again.A, system.A)
    assert list(again.state_labels) == closed.state_names


def test_a_controller_function_sets_the_inputs_the_file_law_computes():
    """The model with its inputs, the inputs set to the law's values at a state, has the right-hand
    side of the model whose file writes the law (what simulate(controller=f) integrates)."""
    from flexkane.kane.inputs import with_control_inputs

    law = Evaluated(flexkane.derive(attitude(ATTITUDE_LAW)))
    open_eom = flexkane.derive(with_control_inputs(attitude(NO_TORQUE)))
    names = [q.name for q in open_eom.q] + [u.name for u in open_eom.u]
    for y in random_states(open_eom, 3):
        state = dict(zip(names, y))
        torque = {f"input_load_attitude_t{c}": -KP_ATT * state[f"q_float_{e}"] - KD_ATT * state[f"u_float_w{c}"]
                  for c, e in zip("xyz", ("e1", "e2", "e3"))}
        controlled = Evaluated(open_eom, torque)
        np.testing.assert_allclose(controlled.rhs(0.0, y), law.rhs(0.0, y), rtol=1e-12, atol=1e-13)


def test_export_control_of_a_spatial_model_from_the_command_line(tmp_path, capsys):
    """``flexkane linearize MODEL --export control`` on a 3D model: statespace.npz with the names of
    the reduced states and the load channels; the attitude modes sqrt(Kp / (2 I_i))."""
    from flexkane.cli import main

    path = tmp_path / "attitude.toml"
    path.write_text(flexkane.dumps_model(attitude(ATTITUDE_LAW)))
    assert main(["linearize", str(path), "--about", "rest", "--export", "control", "--out", str(tmp_path / "o")]) == 0
    data = np.load(tmp_path / "o" / "statespace.npz")
    assert list(data["inputs"]) == [f"input_load_attitude_t{c}" for c in "xyz"]
    assert "rz_float" in list(data["states"]) and "load_attitude_tz" in list(data["outputs"])
    import csv

    with open(tmp_path / "o" / "modes.csv", newline="") as handle:
        rows = [row for row in csv.DictReader(handle) if row["kind"] == "oscillatory"]
    omegas = sorted(float(row["omega_n [rad/s]"]) for row in rows)
    np.testing.assert_allclose(omegas, sorted(np.sqrt(KP_ATT / (2 * np.array(INERTIA)))), rtol=1e-10)
