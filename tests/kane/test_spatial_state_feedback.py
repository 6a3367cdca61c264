"""State feedback, sensors and controller states in spatial chains (dimensions = 3).

Physics is the oracle: a PD law on a revolute joint about a skew axis is the spring and damper of the
same gains (right-hand sides equal to 1e-12); point sensors equal the rigid-body formulas of a turn
about a fixed axis (Rodrigues); the actuator power of feedback laws (a PID torque, an attitude law
written in Euler parameters) is the rate of the mechanical energy along the motion; the saturated
controller output and the controller states' rates are the laws written in the model file.
Evaluated through the compact equations (no compiled module): each test takes a second or two.
"""

from __future__ import annotations

import numpy as np
import pytest
from spatial_control_models import (ATTITUDE_LAW, AXIS, HINGE, KD, KD_ATT, KI, KP, KP_ATT, MOVING_REST, PD_LAW, PID,
                                    Q_REF, SENSED_BEAM, SPRING, STRAIN_FEEDBACK, TOOL, TOP, Evaluated, attitude, hinge,
                                    random_states)

import flexkane
from flexkane.errors import ModelError
from flexkane.model import loads_model


@pytest.fixture(scope="module")
def pd_hinge():
    eom = flexkane.derive(hinge(PD_LAW, sensors=True))
    return eom, Evaluated(eom)


@pytest.fixture(scope="module")
def pid_hinge():
    eom = flexkane.derive(hinge(PID))
    return eom, Evaluated(eom)


@pytest.fixture(scope="module")
def attitude_law():
    eom = flexkane.derive(attitude(ATTITUDE_LAW))
    return eom, Evaluated(eom)


def _close(a, b, rtol=1e-12):
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    assert np.max(np.abs(a - b)) <= rtol * max(np.max(np.abs(b)), 1e-300), (a, b)


def test_pd_law_on_a_spatial_revolute_joint_is_its_spring_and_damper(pd_hinge):
    """torque = -Kp (q - q_ref) - Kd u equals stiffness Kp at rest q_ref with damping Kd; the law
    stays by name in the equations and its value is the output column effort_hinge."""
    eom, law = pd_hinge
    spring = Evaluated(flexkane.derive(hinge(SPRING, sensors=True)))
    for y in random_states(eom, 5):
        _close(law.rhs(0.3, y), spring.rhs(0.3, y))
        out = law.outputs(0.3, y)
        assert out["effort_hinge"] == pytest.approx(-KP * (y[0] - Q_REF) - KD * y[1], rel=1e-14)
    assert {"q_hinge", "u_hinge"} <= {s.name for s in eom.forcing.free_symbols}
    moving = Evaluated(flexkane.derive(hinge(MOVING_REST)))    # a spring whose rest moves with u: an actuator
    for y in random_states(eom, 3):
        _close(moving.rhs(0.3, y), law.rhs(0.3, y))
        out = moving.outputs(0.3, y)
        assert out["potential_springs"] == 0.0
        assert out["power_nonconservative"] == pytest.approx(law.outputs(0.3, y)["power_nonconservative"], rel=1e-12)


def _turn(angle):
    """Rodrigues: the rotation by ``angle`` about AXIS, (3, 3)."""
    k = np.array([[0, -AXIS[2], AXIS[1]], [AXIS[2], 0, -AXIS[0]], [-AXIS[1], AXIS[0], 0]])
    return np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * k @ k


def test_point_sensors_follow_the_rigid_body_formulas(pd_hinge):
    """The tool of a body turning about a fixed axis through the origin: r = R (tool - top),
    v = u a x r, a = u' a x r + u^2 a x (a x r), in ground axes and along the body's axes (R^T);
    joint sensors are the coordinate and the speed."""
    eom, law = pd_hinge
    for y in random_states(eom, 4):
        q, u = y
        ud = law.rhs(0.0, y)[1]
        R = _turn(q)
        r = R @ (TOOL - TOP)
        v = u * np.cross(AXIS, r)
        a = ud * np.cross(AXIS, r) + u ** 2 * np.cross(AXIS, np.cross(AXIS, r))
        out = law.outputs(0.0, y)
        for kind, vector in (("position", r), ("velocity", v), ("acceleration", a)):
            for frame, components in (("ground", vector), ("local", R.T @ vector)):
                got = [out[f"sensor_{kind}_{frame}_{c}"] for c in "xyz"]
                np.testing.assert_allclose(got, components, rtol=0, atol=1e-12 * max(1.0, np.abs(vector).max()))
        assert (out["sensor_angle"], out["sensor_rate"]) == (q, u)


def test_pid_states_rates_and_saturated_output_are_the_laws_of_the_file(pid_hinge):
    """y = [q, u, z]: z' = q_ref - q for the integral, 10 (tool_z - zf) for the filter of a sensor;
    the controller output is the PID law clipped to [-40, 40] and is the hinge's effort."""
    eom, pid = pid_hinge
    assert eom.state_names == ["q_hinge", "u_hinge", "zi", "zf"]
    states = random_states(eom, 3) + [np.array([-9.0, 0.0, 0.0, 0.0]), np.array([9.0, 0.0, 0.0, 0.0])]
    for y in states:
        q, u, zi, zf = y
        out = pid.outputs(0.0, y)
        dy = pid.rhs(0.0, y)
        assert dy[2] == pytest.approx(Q_REF - q, rel=1e-14)
        assert dy[3] == pytest.approx(10 * (out["sensor_tool_z"] - zf), rel=1e-13)
        law = float(np.clip(KP * (Q_REF - q) - KD * u + KI * zi, -40, 40))
        assert out["controller_pid"] == pytest.approx(law, rel=1e-14)
        assert out["effort_hinge"] == out["controller_pid"]
    assert {pid.outputs(0.0, y)["controller_pid"] for y in states[-2:]} == {-40.0, 40.0}


def _energy_rate_and_power(model: Evaluated, y: np.ndarray, h: float = 1e-4):
    """d(energy)/dt along the motion (the derivative of E(t + s, y + s y') at s = 0, by the
    fourth-order central difference) and power_nonconservative."""
    dy = model.rhs(0.0, y)
    E = [model.outputs(s, y + s * dy)["energy"] for s in (-2 * h, -h, h, 2 * h)]
    return (E[0] - 8 * E[1] + 8 * E[2] - E[3]) / (12 * h), model.outputs(0.0, y)["power_nonconservative"]


@pytest.fixture(scope="module")
def strain_feedback():
    eom = flexkane.derive(loads_model(STRAIN_FEEDBACK))
    return eom, Evaluated(eom)


@pytest.mark.parametrize("which", ["pid_hinge", "attitude_law", "strain_feedback"])
def test_actuator_power_of_feedback_is_the_rate_of_energy(which, request):
    """Power balance with feedback: the power of the state-dependent torques (and of the damper-like
    terms of the laws) equals the rate of kinetic plus potential and strain energy; on a hub carrying
    a spatial beam, the torque feeds back the root bending moment and a filtered tip twist."""
    eom, model = request.getfixturevalue(which)
    for y in random_states(eom, 4):
        rate, power = _energy_rate_and_power(model, y)
        assert abs(power) > 1e-3
        assert rate == pytest.approx(power, rel=1e-9, abs=1e-10)


def test_attitude_law_in_euler_parameters_is_the_load_column(attitude_law):
    """T = -Kp e_vec - Kd w in body axes: the columns load_attitude_tx, _ty, _tz."""
    eom, model = attitude_law
    names = [q.name for q in eom.q] + [u.name for u in eom.u]
    for y in random_states(eom, 3):
        state = dict(zip(names, y))
        out = model.outputs(0.0, y)
        for c, e in zip("xyz", ("e1", "e2", "e3")):
            expected = -KP_ATT * state[f"q_float_{e}"] - KD_ATT * state[f"u_float_w{c}"]
            assert out[f"load_attitude_t{c}"] == pytest.approx(expected, rel=1e-14)


@pytest.mark.parametrize("text, path, words", [
    ('[sensors.s]\ntype = "position"\nbody = "arm"\ncomponent = "w"\n', "sensors.s.component", "'z'"),
    ('[sensors.s]\ntype = "tip_deflection"\nbody = "arm"\n', "sensors.s.body", "only beam, component"),
    ('[loads.l]\nbody = "arm"\ntorque = [0, "q_elbow", 0]\n', "loads.l.torque[1]", "unknown name 'q_elbow'"),
    ('[loads.l]\nbody = "arm"\nforce = [0, 1]\n', "loads.l.force", "three values"),
    ('[controllers.c]\nstates = { z = "u_hinge_wx" }\n', "controllers.c.states.z", "unknown name"),
])
def test_spatial_signals_are_checked_by_name(text, path, words):
    with pytest.raises(ModelError) as info:
        loads_model(HINGE.replace("{effort}", PD_LAW) + text)
    assert path in str(info.value) and words in str(info.value)


def test_beam_sensors_name_their_bending_plane_in_3d_and_twist_is_spatial():
    text = SENSED_BEAM.replace('component = "y"\n[sensors.tip_w]', 'component = "x"\n[sensors.tip_w]')
    with pytest.raises(ModelError, match=r"sensors.tip_v.component.*'y'.*EI_z.*'z'"):
        loads_model(text)
    planar = flexkane.builtin_model("flexible-arm")
    planar.sensors["tw"] = flexkane.model.parts.Sensor("tw", "twist", beam=next(iter(planar.beams)), station=0.1)
    with pytest.raises(ModelError, match="sensors.tw.type"):
        planar.validate()


def test_units_of_the_spatial_control_columns(attitude_law, pid_hinge):
    from flexkane.run_manifest import units

    columns = units(attitude_law[0])
    assert {columns[f"load_attitude_t{c}"] for c in "xyz"} == {"N m"}
    columns = units(pid_hinge[0])
    assert (columns["effort_hinge"], columns["sensor_tool_z"], columns["q_hinge"]) == ("N m", "m", "rad")


def test_planar_feedback_through_the_spatial_engine_gives_the_planar_sensors_and_efforts():
    """flexible-arm-pd (a PD law on sensors, a set-point controller, tip and root-strain sensors of
    the beam) through as_spatial: each sensor, controller and effort equals the planar engine's at
    random states (the beam's y bending plane is the planar beam)."""
    from flexkane.model import as_spatial

    planar = flexkane.builtin_model("flexible-arm-pd")
    engines = [flexkane.derive(planar), flexkane.derive(as_spatial(planar))]
    names = [k for k in engines[0].output_names if k.startswith(("sensor_", "controller_", "effort_"))]
    assert len(names) == 6 and set(names) <= set(engines[1].output_names)
    exprs = [[eom.expand(eom.compact.outputs[k]).xreplace(eom.constant_values()) for k in names] for eom in engines]
    rng = np.random.default_rng(3)
    for _ in range(3):
        t, y = float(rng.uniform(0, 2)), rng.standard_normal(len(engines[0].state_names))
        values = [[float(e.xreplace({eom.t: t, **dict(zip([*eom.q, *eom.u], y))})) for e in row]
                  for eom, row in zip(engines, exprs)]
        _close(values[1], values[0])
