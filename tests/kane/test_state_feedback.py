"""State feedback in the loop: efforts of the state, sensors, controller states (physics as the oracle)."""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.integrate
import sympy as sp

import flexkane
from flexkane import linearize
from flexkane.errors import ModelError

HUB_BEAM = """
name = "hub-beam"
[parameters]
J_hub = 0.05
L = 1.0
EI = 12.0
rho = 0.6
Kp = 3.0
q0 = 0.2
[bodies.hub]
mass = 1.0
inertia = "J_hub"
[beams.link]
L = "L"
EI = "EI"
rho = "rho"
n_modes = 2
[joints.shoulder]
type = "revolute"
parent = "ground"
child = "hub"
{law}
[joints.clamp]
type = "weld"
parent = "hub"
child = "link"
[initial]
u_link_1 = 0.3
u_shoulder = 0.5
"""

P_CONTROLLER = 'torque = "-Kp*(q_shoulder - q0)"'
SPRING = 'stiffness = "Kp"\nrest = "q0"'


def _compiled(text):
    return flexkane.compile_model(flexkane.derive(flexkane.loads_model(text)))


def _run(text, compiled=None, **kwargs):
    compiled = compiled or _compiled(text)
    return flexkane.simulate(compiled, **{"t_end": 1.0, "dt_out": 0.01, "rtol": 1e-11, "atol": 1e-12, **kwargs})


@pytest.fixture(scope="module")
def p_and_spring():
    models = [_compiled(HUB_BEAM.format(law=law)) for law in (P_CONTROLLER, SPRING)]
    return models, [_run("", compiled) for compiled in models]


def test_p_controller_equals_torsional_spring_in_simulation(p_and_spring):
    (c_ctrl, c_spring), (ctrl, spring) = p_and_spring
    assert ctrl.state_names == spring.state_names
    # the same right-hand side ...
    rng = np.random.default_rng(1)
    p_ctrl = np.array([ctrl.parameters[n] for n in c_ctrl.derivation.manifest["constant_names"]])
    p_spring = np.array([spring.parameters[n] for n in c_spring.derivation.manifest["constant_names"]])
    for y in rng.uniform(-1, 1, (10, len(ctrl.state_names))):
        f_ctrl, f_spring = c_ctrl.rhs(0.3, y, p_ctrl), c_spring.rhs(0.3, y, p_spring)
        assert np.max(np.abs(f_ctrl - f_spring)) <= 1e-14 * np.max(np.abs(f_spring))
    # ... and the same motion; the steps differ (the actuator's work W, integrated under the same
    # error control, is 0 for the spring), so the trajectories agree to the solver's tolerance
    assert np.max(np.abs(ctrl.state - spring.state)) < 1e-10 * np.max(np.abs(spring.state))
    # the actuator's work is what the spring stores: W = -(k/2) ((q - q0)^2 - (q(0) - q0)^2)
    q = ctrl["q_shoulder"]
    stored = 1.5 * ((q - 0.2) ** 2 - (q[0] - 0.2) ** 2)
    assert np.max(np.abs(ctrl["work"] + stored)) < 1e-9 * np.max(np.abs(ctrl["energy"]))
    assert np.max(np.abs(spring["potential_springs"] - 1.5 * (q - 0.2) ** 2)) < 1e-12
    assert np.allclose(ctrl["effort_shoulder"], -3.0 * (q - 0.2), rtol=0, atol=1e-13)


def test_p_controller_equals_torsional_spring_in_linearization():
    ctrl = linearize(flexkane.loads_model(HUB_BEAM.format(law=P_CONTROLLER)), about="equilibrium")
    spring = linearize(flexkane.loads_model(HUB_BEAM.format(law=SPRING)), about="equilibrium")
    A_c, _ = ctrl.state_space()
    A_s, _ = spring.state_space()
    assert np.max(np.abs(A_c - A_s)) <= 1e-12 * np.max(np.abs(A_s))
    assert np.max(np.abs(ctrl.K - spring.K)) <= 1e-12 * np.max(np.abs(spring.K))


ROTOR = """
name = "rotor-pd"
[parameters]
J = 0.4
Kp = 10.0
Kd = 0.8
ref = 0.3
[bodies.rotor]
mass = 2.0
inertia = "J"
points = { rim = [0.5, 0] }
[joints.axle]
type = "revolute"
parent = "ground"
child = "rotor"
torque = "Kp*(ref - angle) - Kd*rate"
[sensors.angle]
type = "joint_angle"
joint = "axle"
[sensors.rate]
type = "joint_rate"
joint = "axle"
[sensors.rim_x]
type = "acceleration"
body = "rotor"
point = "rim"
frame = "local"
component = "x"
[sensors.rim_y]
type = "acceleration"
body = "rotor"
point = "rim"
frame = "local"
component = "y"
[sensors.rim_vy]
type = "velocity"
body = "rotor"
point = "rim"
frame = "ground"
component = "y"
[initial]
u_axle = 1.0
"""


@pytest.fixture(scope="module")
def rotor():
    return _run(ROTOR, t_end=3.0, dt_out=0.01)


def test_pd_on_a_rigid_rotor_follows_the_damped_response(rotor):
    J, kp, kd, ref = 0.4, 10.0, 0.8, 0.3
    wn = math.sqrt(kp / J)
    zeta = kd / (2 * math.sqrt(kp * J))
    wd = wn * math.sqrt(1 - zeta ** 2)
    t = rotor.t
    a, b = -ref, (1.0 + zeta * wn * (-ref)) / wd     # e(0) = -ref, e'(0) = 1
    exact = ref + np.exp(-zeta * wn * t) * (a * np.cos(wd * t) + b * np.sin(wd * t))
    assert np.max(np.abs(rotor["q_axle"] - exact)) < 1e-9
    assert np.allclose(rotor["sensor_angle"], rotor["q_axle"], rtol=0, atol=0)
    assert np.allclose(rotor["effort_axle"], kp * (ref - exact) - kd * rotor["u_axle"], rtol=0, atol=1e-8)


def test_point_sensors_of_a_rotor(rotor):
    w, r = rotor["u_axle"], 0.5
    alpha = rotor["effort_axle"] / 0.4
    assert np.max(np.abs(rotor["sensor_rim_x"] + w ** 2 * r)) < 1e-10      # centripetal
    assert np.max(np.abs(rotor["sensor_rim_y"] - alpha * r)) < 1e-10       # tangential
    assert np.max(np.abs(rotor["sensor_rim_vy"] - w * r * np.cos(rotor["q_axle"]))) < 1e-12


PID_ARM = """
name = "pid-arm"
[parameters]
J_hub = 0.05
L = 1.0
EI = 12.0
rho = 0.6
c = 0.004
[bodies.hub]
mass = 1.0
inertia = "J_hub"
[beams.link]
L = "L"
EI = "EI"
rho = "rho"
n_modes = 2
[joints.shoulder]
type = "revolute"
parent = "ground"
child = "hub"
torque = "pid"
[joints.clamp]
type = "weld"
parent = "hub"
child = "link"
[sensors.tip]
type = "tip_deflection"
beam = "link"
[sensors.slope]
type = "tip_slope"
beam = "link"
[sensors.moment_root]
type = "bending_moment"
beam = "link"
station = 0
[sensors.strain_root]
type = "strain"
beam = "link"
station = 0
distance = "c"
[controllers.error]
output = "0.5*(1 - cos(2*t)) - q_shoulder"
[controllers.pid]
states = { integral = "error" }
initial = { integral = 0.01 }
output = "8*error + 4*integral - 1.5*u_shoulder"
min = -0.4
max = 0.4
"""


@pytest.fixture(scope="module")
def pid_arm():
    return _run(PID_ARM, t_end=2.0, dt_out=0.002)


def test_integral_state_is_the_quadrature_of_its_input(pid_arm):
    integral = scipy.integrate.cumulative_simpson(pid_arm["controller_error"], x=pid_arm.t, initial=0.0)
    assert pid_arm.state_names[-1] == "integral"
    assert np.max(np.abs(pid_arm["integral"] - 0.01 - integral)) < 1e-9


def test_saturation_and_power_balance_with_feedback(pid_arm):
    torque = pid_arm["effort_shoulder"]
    assert np.max(torque) == pytest.approx(0.4, abs=1e-12) and np.min(torque) >= -0.4 - 1e-12
    unsaturated = 8 * pid_arm["controller_error"] + 4 * pid_arm["integral"] - 1.5 * pid_arm["u_shoulder"]
    assert np.allclose(torque, np.clip(unsaturated, -0.4, 0.4), rtol=0, atol=1e-12)
    # actuator power integrated = change of kinetic + strain energy, to the solver's tolerance
    e = pid_arm["kinetic"] + pid_arm["strain"]
    assert np.max(np.abs(e - e[0] - pid_arm["work"])) < 1e-8 * np.max(np.abs(e))
    power = torque * pid_arm["u_shoulder"]
    assert np.allclose(pid_arm["power_nonconservative"], power, rtol=0, atol=1e-12)


def test_beam_sensors(pid_arm):
    from flexkane.modes import get_family

    family = get_family("clamped-free")
    q = np.stack([pid_arm["q_link_1"], pid_arm["q_link_2"]])
    tip = family.phi(np.array([1.0]), 2)[:, 0] @ q
    slope = family.phi(np.array([1.0]), 2, deriv=1)[:, 0] @ q / 1.0
    curvature = family.phi(np.array([0.0]), 2, deriv=2)[:, 0] @ q / 1.0 ** 2
    assert np.allclose(pid_arm["sensor_tip"], pid_arm["tip_link"], rtol=0, atol=1e-15)
    assert np.allclose(pid_arm["sensor_tip"], tip, rtol=1e-10, atol=1e-15)
    assert np.allclose(pid_arm["sensor_slope"], slope, rtol=1e-10, atol=1e-15)
    assert np.allclose(pid_arm["sensor_moment_root"], 12.0 * curvature, rtol=1e-10, atol=1e-14)
    assert np.allclose(pid_arm["sensor_strain_root"], -0.004 * curvature, rtol=1e-10, atol=1e-18)


# ------------------------------------------------------------------------------ errors
def _model(text, **changes):
    return flexkane.loads_model(text).with_values(changes, validate=False)


def test_unknown_name_in_an_effort_says_which_names_are_allowed():
    with pytest.raises(ModelError) as info:
        _model(ROTOR, **{"joints.axle.torque": "Kp*(ref - angel)"}).validate()
    text = str(info.value)
    assert info.value.path == "joints.axle.torque"
    assert "unknown name 'angel'" in text
    for allowed in ("q_axle", "u_axle", "sensors (angle, rate, rim_vy)", "parameters"):
        assert allowed in text


def test_acceleration_sensor_in_an_effort_is_refused():
    with pytest.raises(ModelError) as info:
        _model(ROTOR, **{"joints.axle.torque": "-0.1*rim_y"}).validate()
    assert info.value.path == "joints.axle.torque"
    assert "u'" in str(info.value) and "rim_y" in str(info.value)


def test_cycle_between_controller_outputs_is_refused():
    text = PID_ARM.replace('output = "0.5*(1 - cos(2*t)) - q_shoulder"', 'output = "pid - q_shoulder"')
    with pytest.raises(ModelError) as info:
        flexkane.loads_model(text)
    assert "cycle" in str(info.value) and "pid" in str(info.value) and "error" in str(info.value)


def test_acceleration_sensor_in_a_controller_is_refused():
    text = ROTOR + '\n[controllers.filter]\nstates = { a_f = "10*(rim_x - a_f)" }\n'
    with pytest.raises(ModelError) as info:
        flexkane.loads_model(text)
    assert info.value.path == "controllers.filter.states.a_f" and "u'" in str(info.value)


def test_driver_depending_on_the_speeds_is_refused():
    """A driver's law may read the coordinates (tests/kane/test_driver_laws_of_the_state.py), not the speeds."""
    text = ROTOR.replace('torque = "Kp*(ref - angle) - Kd*rate"', 'driver = { speed = "-angle - 0.1*rate" }')
    text = text.replace("u_axle = 1.0", "q_axle = 1.0")
    with pytest.raises(ModelError) as info:
        flexkane.loads_model(text)
    assert info.value.path == "joints.axle.driver.speed"
    assert "rate (a joint_rate sensor)" in str(info.value) and "u'" in str(info.value) and "torque" in str(info.value)


def test_signal_names_must_be_new():
    text = ROTOR + '\n[controllers.c]\nstates = { q_axle = "1" }\n'
    with pytest.raises(ModelError) as info:
        flexkane.loads_model(text)
    assert info.value.path == "controllers.c.states.q_axle" and "already used" in str(info.value)


def test_linear_model_with_a_controller_state_is_the_open_loop_closed_by_the_pid():
    """The PID's integral is a state of the linear model: x = (dq, du, dz), and A equals the open-loop
    arm's A - B K with the gains of the law (torque = 8 e + 4 z - 1.5 u, z' = e, e = ref - q) to 1e-12.
    Its initial integral 0.01 pushes the arm at rest, which is no equilibrium; the equilibrium has z = 0."""
    from flexkane.analysis.equilibrium import NoEquilibriumError

    model = flexkane.loads_model(PID_ARM)
    with pytest.raises(NoEquilibriumError, match="not in equilibrium at rest"):
        linearize(model, about="rest")
    closed = linearize(model)
    assert closed.state_names[-1] == "integral" and closed.z0 == pytest.approx([0.0], abs=1e-12)
    open_model = model.copy()
    open_model.joints["shoulder"].torque = None
    open_model.controllers = {}
    opened = linearize(open_model.validate())
    A_o, B_o = opened.state_space()
    b = B_o[:, opened.input_names.index("input_effort_shoulder")]
    n = opened.n
    expected = np.zeros((2 * n + 1, 2 * n + 1))
    expected[:2 * n, :2 * n] = A_o - np.outer(b, 8.0 * np.eye(2 * n)[opened.state_names.index("q_shoulder")]
                                               + 1.5 * np.eye(2 * n)[opened.state_names.index("u_shoulder")])
    expected[:2 * n, 2 * n] = 4.0 * b
    expected[2 * n, opened.state_names.index("q_shoulder")] = -1.0
    A, B = closed.state_space()
    assert closed.state_names[:2 * n] == opened.state_names
    np.testing.assert_allclose(A, expected, rtol=0, atol=1e-12 * np.abs(expected).max())
    np.testing.assert_allclose(B[:, closed.input_names.index("input_effort_shoulder")], np.append(b, 0.0),
                               rtol=0, atol=1e-12 * np.abs(b).max())


def test_model_file_round_trip_keeps_sensors_and_controllers():
    model = flexkane.loads_model(PID_ARM)
    again = flexkane.loads_model(flexkane.dumps_model(model))
    assert again.sensors == model.sensors and again.controllers == model.controllers


def test_a_moving_rest_position_makes_the_spring_an_actuator_counted_in_the_work():
    text = ROTOR.replace('torque = "Kp*(ref - angle) - Kd*rate"',
                         'stiffness = "Kp"\ndamping = "Kd"\nrest = "ref*sin(2*t) + 0.1*rate"')
    run = _run(text, t_end=2.0, dt_out=0.01)
    q, w = run["q_axle"], run["u_axle"]
    spring = -10.0 * (q - (0.3 * np.sin(2 * run.t) + 0.1 * w))
    assert np.all(run["potential_springs"] == 0)
    assert np.allclose(run["power_nonconservative"], (spring - 0.8 * w) * w, rtol=0, atol=1e-12)
    assert np.max(np.abs(run["energy_balance"])) < 1e-9 * np.max(run["energy"])


def test_set_values_of_controllers():
    model = flexkane.loads_model(PID_ARM).with_values({"controllers.pid.max": 0.5,
                                                       "controllers.pid.initial.integral": 0.2})
    assert model.controllers["pid"].max == 0.5 and model.controllers["pid"].initial == {"integral": 0.2}
    with pytest.raises(ModelError) as info:
        model.with_values({"controllers.pid.initial.other": 1.0})
    assert info.value.path == "controllers.pid.initial.other" and "integral" in str(info.value)


def _hub_beam_spring_frequencies(J, L, EI, rho, k, count):
    """Roots of the frequency equation of a hub (inertia J, torsional spring k) carrying a clamped
    Euler-Bernoulli beam: w(0) = 0, w'(0) = theta, J theta'' + k theta = EI w''(0), free tip [rad/s]."""
    from scipy.optimize import brentq

    def det(beta):
        h = k - J * EI * beta ** 4 / rho
        b = beta * L
        rows = [[1, 0, 1, 0], [-EI * beta ** 2, h * beta, EI * beta ** 2, h * beta],
                [np.cosh(b), np.sinh(b), -np.cos(b), -np.sin(b)], [np.sinh(b), np.cosh(b), np.sin(b), -np.cos(b)]]
        return np.linalg.det(np.array(rows)) / np.cosh(b)

    grid = np.linspace(0.05, 4 * (count + 1) / L, 4000)
    values = [det(b) for b in grid]
    roots = [brentq(det, a, b, xtol=1e-14) for a, b, fa, fb in zip(grid, grid[1:], values, values[1:])
             if np.sign(fa) != np.sign(fb)]
    return math.sqrt(EI / rho) * np.array(roots[:count]) ** 2


@pytest.mark.slow
def test_closed_loop_frequencies_converge_to_the_hub_beam_frequency_equation():
    from flexkane.analysis import modal_analysis

    text = HUB_BEAM.format(law='torque = "-Kp*q_shoulder"')
    exact = _hub_beam_spring_frequencies(0.05, 1.0, 12.0, 0.6, 3.0, 3)
    errors = []
    for n in (2, 4, 8):
        model = flexkane.loads_model(text).with_modes(n)
        frequencies = modal_analysis(linearize(model, about="rest")).frequencies[:3]
        errors.append(np.abs(frequencies - exact) / exact)
    assert np.all(errors[1] < errors[0]) and np.all(errors[2] < errors[1])
    assert np.max(errors[2]) < 1e-7     # measured 9.3e-9


def test_feedback_is_printed_by_name_in_the_equations():
    from flexkane.report import format_equations

    eom = flexkane.derive(flexkane.builtin_model("flexible-arm-pid"))
    lines = format_equations(eom).splitlines()
    assert "F[u_shoulder]_loads = motor - tau_d" in lines          # F_r of the hub: the controller by name
    # each signal defined once, in terms of the signals defined before it (chains print in linear size)
    assert "error = -q_shoulder + theta_f" in lines
    assert "motor = Max(min_motor, Min(tau_max, -Kd*u_shoulder + Ki*error_integral + Kp*error))" in lines
    assert "error_integral' = error" in lines
    assert eom.state_names[-1] == "error_integral" and list(eom.zdot) == [sp.Symbol("theta_f", real=True)
                                                                            - eom.q[0]]


@pytest.mark.parametrize("change, path, words", [
    ({"sensors.tip.beam": "hub"}, "sensors.tip.beam", "the name of a beam"),
    ({"sensors.tip.station": 0.5}, "sensors.tip.station", "only beam"),
    ({"sensors.tip.type": "tip"}, "sensors.tip.type", "tip_deflection"),
    ({"controllers.motor.max": "-2*tau_max"}, "controllers.motor.max", "above the minimum"),
    ({"controllers.motor.states.error_integral": "error + hub_rate"}, "controllers.motor.states.error_integral",
     "unknown name 'hub_rate'"),
])
def test_sensor_and_controller_fields_are_checked(change, path, words):
    with pytest.raises(ModelError) as info:
        flexkane.builtin_model("flexible-arm-pid").with_values(change)
    assert info.value.path == path and words in str(info.value)
