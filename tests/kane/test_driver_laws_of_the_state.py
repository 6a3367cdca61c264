"""Drivers whose law reads the state (a gear, a cam, a filtered reference): physics as the oracle.

A coordinate driver ``q_d = L(t, q, z)`` is a holonomic constraint enforced by ideal forces
(:mod:`flexkane.kane.driver_laws`): the independent derivation is ``sympy.physics.mechanics``'
KanesMethod with that configuration constraint and the driven speed dependent.
"""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp
from sympy.physics.mechanics import KanesMethod, Point, ReferenceFrame, RigidBody, dynamicsymbols, inertia

import flexkane
from flexkane.errors import ModelError
from flexkane.expressions import parse_expression

#: Two rigid links on revolute joints, the second driven by a law of the first's angle.
GEARED = """
name = "geared"
[parameters]
m1 = 1.0
m2 = 0.7
I1 = 0.05
I2 = 0.03
c = 0.5
g = 9.81
[gravity]
g = "g"
direction = [0, -1]
[bodies.a]
mass = "m1"
inertia = "I1"
points = {{ hinge = [-0.4, 0.0], tip = [0.4, 0.0] }}
[bodies.b]
mass = "m2"
inertia = "I2"
points = {{ hinge = [-0.3, 0.0] }}
[joints.sa]
type = "revolute"
parent = "ground"
child = "a"
child_point = "hinge"
[joints.sb]
type = "revolute"
parent = "a"
parent_point = "tip"
child = "b"
child_point = "hinge"
driver = {{ coordinate = "{law}" }}
[initial]
q_sa = 0.3
"""


def _geared_accelerations(N, symbols, L, bodies, loads):
    """u_a' by KanesMethod of two joints (coordinates and speeds ``symbols = (qa, qb, ua, ub)``, the
    speeds the coordinates' rates) with the configuration constraint ``qb - L(qa, t) = 0``, as a
    function of (qa, ua, t)."""
    t = dynamicsymbols._t
    qa, qb, ua, ub = symbols
    kane = KanesMethod(N, q_ind=[qa], q_dependent=[qb], u_ind=[ua], u_dependent=[ub],
                       kd_eqs=[qa.diff(t) - ua, qb.diff(t) - ub],
                       configuration_constraints=[qb - L],
                       velocity_constraints=[ub - L.diff(t).subs(qa.diff(t), ua)])
    kane.kanes_equations(bodies, loads)
    X = sp.symbols("QA QB UA UB T")
    plain = dict(zip([qa, qb, ua, ub, t], X))
    M, f = (sp.lambdify(X, e.xreplace(plain), "numpy", cse=True) for e in (kane.mass_matrix, kane.forcing))
    speed = sp.lambdify([X[0], X[2], X[4]], L.diff(t).subs(qa.diff(t), ua).xreplace(plain), "numpy", cse=True)
    angle = sp.lambdify([X[0], X[4]], L.xreplace(plain), "numpy", cse=True)

    def accelerations(q, u, time):
        state = (q, angle(q, time), u, speed(q, u, time), time)
        return np.linalg.solve(np.atleast_2d(M(*state)), np.ravel(f(*state)))[0]
    return accelerations


def _kanes_method_accelerations(law):
    """u_sa' of the chain by KanesMethod with ``q_sb - law(q_sa, t) = 0``, as a function of (q_sa, u_sa, t)."""
    t = dynamicsymbols._t
    qa, qb, ua, ub = dynamicsymbols("qa qb ua ub")
    m1, m2, I1, I2, c, g = 1.0, 0.7, 0.05, 0.03, 0.5, 9.81
    N = ReferenceFrame("N")
    A = N.orientnew("A", "Axis", (qa, N.z))
    B = A.orientnew("B", "Axis", (qb, A.z))
    A.set_ang_vel(N, ua * N.z)
    B.set_ang_vel(A, ub * A.z)
    O = Point("O")
    O.set_vel(N, 0)
    Ac = O.locatenew("Ac", 0.4 * A.x)
    Ac.v2pt_theory(O, N, A)
    hinge = O.locatenew("H", 0.8 * A.x)
    hinge.v2pt_theory(O, N, A)
    Bc = hinge.locatenew("Bc", 0.3 * B.x)
    Bc.v2pt_theory(hinge, N, B)
    bodies = [RigidBody("a", Ac, A, m1, (inertia(A, 0, 0, I1), Ac)),
              RigidBody("b", Bc, B, m2, (inertia(B, 0, 0, I2), Bc))]
    loads = [(Ac, -m1 * g * N.y), (Bc, -m2 * g * N.y)]
    L = law(qa, t, c)
    return _geared_accelerations(N, (qa, qb, ua, ub), L, bodies, loads)


def _flexkane_accelerations(eom):
    values = eom.constant_values()
    M, f = (sp.lambdify([*eom.q, *eom.u, eom.t], eom.expand(e).xreplace(values), "numpy", cse=True)
            for e in (eom.compact.mass_matrix, eom.compact.forcing))
    return lambda *state: np.linalg.solve(np.atleast_2d(M(*state)), np.ravel(f(*state)))[0]


def test_a_gear_law_is_kanes_method_with_the_holonomic_constraint():
    """A gear ``q_sb = c q_sa`` with a cam term read by a position sensor (the height of a's tip,
    0.8 sin(q_sa) [m]) and a term of t: u_sa' at random states to 1e-10."""
    text = "c*q_sa + 0.25*tip_y + 0.1*sin(2*t)"
    sensor = '\n[sensors.tip_y]\ntype = "position"\nbody = "a"\npoint = "tip"\ncomponent = "y"\n'

    def law(qa, t, c):
        return c * qa + 0.2 * sp.sin(qa) + 0.1 * sp.sin(2 * t)

    eom = flexkane.derive(flexkane.loads_model(GEARED.format(law=text) + sensor))
    assert [q.name for q in eom.q] == ["q_sa"] and [u.name for u in eom.u] == ["u_sa"]
    ours, theirs = _flexkane_accelerations(eom), _kanes_method_accelerations(law)
    rng = np.random.default_rng(18)
    for qa, ua, t in rng.uniform(-2.0, 2.0, size=(6, 3)):
        expected = theirs(qa, ua, t)
        assert abs(ours(qa, ua, t) - expected) <= 1e-10 * max(1.0, abs(expected))


#: A rigid link with an actuator torque carrying, on a joint at its tip, a beam driven by a law of
#: the link's angle and of t; no gravity.
GEARED_BEAM = """
name = "geared-beam"
[parameters]
c = 0.5
[bodies.a]
mass = 1.0
inertia = 0.05
points = { hinge = [-0.4, 0.0], tip = [0.4, 0.0] }
[beams.link]
L = 1.0
EI = 12.0
rho = 0.6
n_modes = 2
[joints.sa]
type = "revolute"
parent = "ground"
child = "a"
child_point = "hinge"
torque = "0.8*sin(2*t) - 0.3*q_sa"
[joints.sb]
type = "revolute"
parent = "a"
parent_point = "tip"
child = "link"
driver = { coordinate = "c*q_sa + 0.1*sin(3*t)" }
"""


def test_power_of_the_driver_and_the_actuator_is_the_rate_of_kinetic_and_strain_energy():
    """d(T + V_strain)/dt = tau u_sa + lambda (u_sb - c u_sa) at random states: the driver's effort
    lambda acts on its joint and, as a gear does, -c lambda on the joint its law reads."""
    eom = flexkane.derive(flexkane.loads_model(GEARED_BEAM))
    assert [u.name for u in eom.u] == ["u_sa", "u_link_1", "u_link_2"]
    values = eom.constant_values()
    t = eom.t
    ud = sp.symbols("a0:3")
    rates = dict(zip(eom.ud, ud))
    out = {k: eom.outputs[k].xreplace(values).xreplace(rates) for k in
           ("kinetic", "strain", "effort_sb", "effort_sa", "power_nonconservative")}
    energy = out["kinetic"] + out["strain"]
    qdot = list(eom.qdot.xreplace(values))
    rate = (sum(energy.diff(q) * qd for q, qd in zip(eom.q, qdot)) + sum(energy.diff(u) * a for u, a in zip(eom.u, ud))
            + energy.diff(t))
    u_sa = eom.u[0]
    u_sb = 0.5 * u_sa + 0.3 * sp.cos(3 * t)        # the law's time derivative, written here
    supplied = out["effort_sa"] * u_sa + out["effort_sb"] * (u_sb - 0.5 * u_sa)
    args = [*eom.q, *eom.u, t]
    M, f = (sp.lambdify(args, eom.expand(e).xreplace(values), "numpy", cse=True)
            for e in (eom.compact.mass_matrix, eom.compact.forcing))
    check = sp.lambdify([*args, *ud], [rate, supplied, out["power_nonconservative"], out["effort_sa"]], "numpy",
                        cse=True)
    rng = np.random.default_rng(7)
    for state in rng.uniform(-1.0, 1.0, size=(5, 7)):
        acc = np.linalg.solve(M(*state), np.ravel(f(*state)))
        de, power, reported, torque = check(*state, *acc)
        assert abs(torque - (0.8 * np.sin(2 * state[-1]) - 0.3 * state[0])) <= 1e-14
        assert abs(de - power) <= 1e-10 * max(1.0, abs(de))
        assert abs(reported - power) <= 1e-10 * max(1.0, abs(power))


def _finite_difference_jacobian(fun, x, h=1e-6):
    columns = [(fun(x + h * e) - fun(x - h * e)) / (2 * h) for e in np.eye(len(x))]
    return np.array(columns).T


def test_linearize_with_a_gear_reduces_the_driven_coordinate():
    """The geared pendulum at its hanging equilibrium: the linear model's states are (q_sa, u_sa) only,
    and A equals the finite-difference Jacobian of the nonlinear right-hand side there."""
    from flexkane import linearize

    model = flexkane.loads_model(GEARED.format(law="c*q_sa"))
    linear = linearize(model, about="equilibrium")
    A, _ = linear.state_space()
    assert A.shape == (2, 2)
    eom = flexkane.derive(model)
    accelerations = _flexkane_accelerations(eom)

    def rhs(x):
        return np.array([x[1], accelerations(x[0], x[1], 0.0)])

    assert linear.state_names == ["q_sa", "u_sa"]
    q0 = float(linear.q0[0])
    assert abs(rhs(np.array([q0, 0.0]))[1]) < 1e-10
    J = _finite_difference_jacobian(rhs, np.array([q0, 0.0]))
    assert np.max(np.abs(A - J)) <= 1e-7 * np.max(np.abs(J))


#: Two drivers of the state on one chain: sb follows a's angle and the tip deflection of the beam
#: that sc carries (a sensor of its modal coordinate), sc follows a's angle and t.
TWO_DRIVERS = """
name = "three"
[bodies.a]
mass = 1.0
inertia = 0.05
points = { hinge = [-0.4, 0.0], tip = [0.4, 0.0] }
[bodies.b]
mass = 0.7
inertia = 0.03
points = { hinge = [-0.3, 0.0], tip = [0.3, 0.0] }
[beams.link]
L = 1.0
EI = 12.0
rho = 0.6
n_modes = 1
[sensors.tipdef]
type = "tip_deflection"
beam = "link"
[joints.sa]
type = "revolute"
parent = "ground"
child = "a"
child_point = "hinge"
[joints.sb]
type = "revolute"
parent = "a"
parent_point = "tip"
child = "b"
child_point = "hinge"
driver = { coordinate = "0.5*q_sa + 0.3*tipdef" }
[joints.sc]
type = "revolute"
parent = "b"
parent_point = "tip"
child = "link"
driver = { coordinate = "-0.2*q_sa + 0.1*sin(t)" }
"""


def test_two_drivers_of_the_state_keep_the_energy_balance():
    """d(energy)/dt = power_nonconservative (the drivers' forces on their joints and on the coordinates
    their laws read, modal ones included) at random states."""
    eom = flexkane.derive(flexkane.loads_model(TWO_DRIVERS))
    assert eom.state_names == ["q_sa", "q_link_1", "u_sa", "u_link_1"]
    balance = _energy_balance(eom)
    rng = np.random.default_rng(11)
    for state in rng.uniform(-1.0, 1.0, size=(3, len(eom.q) + len(eom.u) + 1)):
        de, supplied = balance(state)
        assert abs(de - supplied) <= 1e-10 * max(1.0, abs(de))


def _energy_balance(eom):
    """``state -> (d(energy)/dt, power_nonconservative)`` along the equations, ``state = [q, u, t]``."""
    values = eom.constant_values()
    t = eom.t
    ud = sp.symbols(f"a0:{len(eom.u)}")
    rates = dict(zip(eom.ud, ud))
    energy, power = (eom.outputs[k].xreplace(values).xreplace(rates) for k in ("energy", "power_nonconservative"))
    qdot = list(eom.qdot.xreplace(values))
    rate = (sum(energy.diff(q) * qd for q, qd in zip(eom.q, qdot)) + sum(energy.diff(u) * a for u, a in zip(eom.u, ud))
            + energy.diff(t))
    args = [*eom.q, *eom.u, t]
    M, f = (sp.lambdify(args, eom.expand(e).xreplace(values), "numpy", cse=True)
            for e in (eom.compact.mass_matrix, eom.compact.forcing))
    check = sp.lambdify([*args, *ud], [rate, power], "numpy", cse=True)
    return lambda state: check(*state, *np.linalg.solve(np.atleast_2d(M(*state)), np.ravel(f(*state))))


#: A first-order filter z_f' = (r(t) - z_f)/tau of the reference r = R sin(w t), z_f(0) = 0, and its
#: closed form.
FILTER = '\n[controllers.filter]\nstates = { z_f = "(0.4*sin(3*t) - z_f)/0.2" }\n'
FILTERED = "0.4/(1 + 0.36)*(sin(3*t) - 0.6*cos(3*t) + 0.6*exp(-t/0.2))"


def test_a_driver_following_a_filtered_reference_is_the_closed_form_law():
    """q_sb = c q_sa + z_f with the filter's state equals q_sb = c q_sa + (its closed form in t):
    the accelerations agree at random states where z_f has its closed-form value, and z_f' is the
    closed form's derivative there."""
    with_state = flexkane.derive(flexkane.loads_model(GEARED.format(law="c*q_sa + z_f") + FILTER))
    closed = flexkane.derive(flexkane.loads_model(GEARED.format(law=f"c*q_sa + {FILTERED}")))
    assert [z.name for z in with_state.z] == ["z_f"]
    t = closed.t
    z_of_t = parse_expression(FILTERED, {"t": t}, path="law")
    values = with_state.constant_values()
    args = [*with_state.q, *with_state.u, *with_state.z, t]
    M, f, zdot = (sp.lambdify(args, e.xreplace(values), "numpy", cse=True)
                  for e in (with_state.mass_matrix, with_state.forcing, with_state.zdot))
    reference = _flexkane_accelerations(closed)
    z_f, z_rate = sp.lambdify([t], z_of_t), sp.lambdify([t], z_of_t.diff(t))
    rng = np.random.default_rng(3)
    for qa, ua, time in rng.uniform([-2.0, -2.0, 0.0], [2.0, 2.0, 3.0], size=(6, 3)):
        z = z_f(time)
        ours = np.linalg.solve(np.atleast_2d(M(qa, ua, z, time)), np.ravel(f(qa, ua, z, time)))[0]
        expected = reference(qa, ua, time)
        assert abs(ours - expected) <= 1e-10 * max(1.0, abs(expected))
        assert abs(float(np.ravel(zdot(qa, ua, z, time))[0]) - z_rate(time)) <= 1e-12


@pytest.mark.slow
def test_a_run_following_a_filtered_reference_is_the_run_with_the_closed_form_law():
    """The same two models integrated for 3 s: q_sa, u_sa and the driver's effort agree to 1e-8."""
    runs = []
    for text in (GEARED.format(law="c*q_sa + z_f") + FILTER, GEARED.format(law=f"c*q_sa + {FILTERED}")):
        compiled = flexkane.compile_model(flexkane.derive(flexkane.loads_model(text)))
        runs.append(flexkane.simulate(compiled, t_end=3.0, dt_out=0.01, rtol=1e-12, atol=1e-12))
    ours, theirs = runs
    for name in ("q_sa", "u_sa", "effort_sb"):
        scale = max(1.0, float(np.max(np.abs(theirs[name]))))
        assert np.max(np.abs(ours[name] - theirs[name])) <= 1e-8 * scale, name
    assert np.max(np.abs(ours["energy_balance"])) <= 1e-8 * max(1.0, float(np.max(np.abs(ours["energy"]))))


VELOCITY_SENSOR = '\n[sensors.v]\ntype = "velocity"\nbody = "a"\npoint = "tip"\ncomponent = "x"\n'


@pytest.mark.parametrize("law, extra, says", [
    ("c*u_sa", "", "u_sa (a speed)"),
    ("v", VELOCITY_SENSOR, "v (a velocity sensor)"),
    ("z", '\n[controllers.k]\nstates = { z = "u_sa - z" }\n', "rate reads u_sa"),
    ("k", '\n[controllers.k]\noutput = "2*u_sa"\n', "through controller output 'k'"),
    ("q_sa + 0.1*q_sb", "", "q_sb (its own coordinate)"),
])
def test_a_driver_law_of_speeds_is_refused_by_name(law, extra, says):
    with pytest.raises(ModelError) as info:
        flexkane.loads_model(GEARED.format(law=law) + extra)
    assert info.value.path == "joints.sb.driver.coordinate"
    assert says in str(info.value) and "u'" in str(info.value) and "torque" in str(info.value)


def test_a_driver_law_reading_a_sensor_its_joint_moves_is_refused():
    """A position sensor on the driven link reads the driven coordinate: q = L(q) is no prescription
    (validation finds the driven joint on the sensor's path from the ground)."""
    text = GEARED.format(law="p") + '\n[sensors.p]\ntype = "position"\nbody = "b"\ncomponent = "x"\n'
    with pytest.raises(ModelError) as info:
        flexkane.loads_model(text)
    assert info.value.path == "joints.sb.driver.coordinate" and "which the driven joint sb moves" in str(info.value)


def test_the_command_line_refuses_a_driver_law_of_speeds_with_exit_2(tmp_path, capsys):
    from flexkane.cli import main

    path = tmp_path / "geared.toml"
    path.write_text(GEARED.format(law="c*u_sa"))
    assert main(["check", str(path)]) == 2
    assert "joints.sb.driver.coordinate" in capsys.readouterr().err


def test_the_report_prints_a_law_of_the_state_by_name():
    """equations.md gives the driven coordinate's law with the sensor and the controller state by name,
    and their definitions (the sensor's in q, the state's rate)."""
    from flexkane.report import equations_markdown

    sensor = '\n[sensors.tip_y]\ntype = "position"\nbody = "a"\npoint = "tip"\ncomponent = "y"\n'
    eom = flexkane.derive(flexkane.loads_model(GEARED.format(law="c*q_sa + z_f + 0.1*tip_y") + FILTER + sensor))
    text = equations_markdown(eom, eom.constant_values())
    assert r"(driven: $c q_{sa} + 0.1 tip_{y} + z_{f}$ coordinate)" in text
    assert r"tip_{y} &=" in text and r"\dot{z_{f}} &=" in text


#: A spatial chain: a waist about the vertical carrying link a, and on a's shoulder, about a's x axis,
#: link b driven by a law of the waist angle, of a position sensor and of t; full inertia tensors,
#: gravity along -z, an actuator torque on the waist.
SPATIAL_GEARED = """
dimensions = 3
name = "spatial-geared"
[parameters]
c = 0.5
[gravity]
g = 9.81
direction = [0, 0, -1]
[bodies.a]
mass = 2.0
inertia = [[0.1, 0.01, 0.0], [0.01, 0.2, 0.02], [0.0, 0.02, 0.15]]
points = {{ base = [-0.1, 0.0, -0.2], hinge = [-0.1, 0.1, 0.1] }}
[bodies.b]
mass = 1.5
inertia = [[0.05, 0.0, 0.01], [0.0, 0.07, 0.0], [0.01, 0.0, 0.03]]
points = {{ hinge = [0.0, -0.4, 0.0] }}
[sensors.hinge_x]
type = "position"
body = "a"
point = "hinge"
component = "x"
[joints.waist]
type = "revolute"
parent = "ground"
child = "a"
child_point = "base"
axis = [0, 0, 1]
torque = "0.3*sin(t)"
[joints.shoulder]
type = "revolute"
parent = "a"
parent_point = "hinge"
child = "b"
child_point = "hinge"
axis = [1, 0, 0]
driver = {{ coordinate = "{law}" }}
"""


def _kanes_method_spatial_geared(law):
    """u_waist' of SPATIAL_GEARED by KanesMethod with ``q_shoulder - law(q_waist, t) = 0``, as a function
    of (q_waist, u_waist, t)."""
    t = dynamicsymbols._t
    qa, qb, ua, ub = dynamicsymbols("qa qb ua ub")
    N = ReferenceFrame("N")
    A = N.orientnew("A", "Axis", (qa, N.z))
    B = A.orientnew("B", "Axis", (qb, A.x))
    A.set_ang_vel(N, ua * N.z)
    B.set_ang_vel(A, ub * A.x)
    O = Point("O")
    O.set_vel(N, 0)
    Ac = O.locatenew("Ac", 0.1 * A.x + 0.2 * A.z)        # a's base point is at the origin
    Ac.v2pt_theory(O, N, A)
    hinge = Ac.locatenew("H", -0.1 * A.x + 0.1 * A.y + 0.1 * A.z)
    hinge.v2pt_theory(O, N, A)
    Bc = hinge.locatenew("Bc", 0.4 * B.y)
    Bc.v2pt_theory(hinge, N, B)
    bodies = [RigidBody("a", Ac, A, 2.0, (inertia(A, 0.1, 0.2, 0.15, 0.01, 0.02, 0.0), Ac)),
              RigidBody("b", Bc, B, 1.5, (inertia(B, 0.05, 0.07, 0.03, 0.0, 0.0, 0.01), Bc))]
    loads = [(Ac, -2.0 * 9.81 * N.z), (Bc, -1.5 * 9.81 * N.z), (A, 0.3 * sp.sin(t) * N.z)]
    L = law(qa, t, hinge.pos_from(O).dot(N.x))
    return _geared_accelerations(N, (qa, qb, ua, ub), L, bodies, loads)


def test_a_spatial_gear_law_is_kanes_method_with_the_holonomic_constraint():
    """A spatial chain (shoulder about a horizontal axis carried by a waist about the vertical) whose
    shoulder follows the waist angle, the x of a's hinge (a position sensor, -0.1 sin(q_waist) [m])
    and t: u_waist' at random states equals KanesMethod's with that configuration constraint, to 1e-10."""
    text = "c*q_waist + 0.5*hinge_x + 0.1*sin(2*t)"
    eom = flexkane.derive(flexkane.loads_model(SPATIAL_GEARED.format(law=text)))
    assert [q.name for q in eom.q] == ["q_waist"] and [u.name for u in eom.u] == ["u_waist"]
    ours = _flexkane_accelerations(eom)
    theirs = _kanes_method_spatial_geared(lambda qa, t, x: 0.5 * qa + 0.5 * x + 0.1 * sp.sin(2 * t))
    rng = np.random.default_rng(26)
    for qa, ua, t in rng.uniform(-2.0, 2.0, size=(6, 3)):
        expected = theirs(qa, ua, t)
        assert abs(ours(qa, ua, t) - expected) <= 1e-10 * max(1.0, abs(expected))


def test_a_spatial_gear_keeps_the_energy_balance_and_reads_no_own_coordinate():
    """The spatial gear ``q_shoulder = c q_waist`` (no t): d(energy)/dt = power_nonconservative = the
    waist's actuator power at random states (the gear does no work); a law of its own coordinate is
    refused by name as in a planar model."""
    eom = flexkane.derive(flexkane.loads_model(SPATIAL_GEARED.format(law="c*q_waist")))
    balance = _energy_balance(eom)
    rng = np.random.default_rng(5)
    for qa, ua, time in rng.uniform(-2.0, 2.0, size=(4, 3)):
        de, supplied = balance([qa, ua, time])
        assert abs(de - supplied) <= 1e-10 * max(1.0, abs(de))
        assert abs(supplied - 0.3 * np.sin(time) * ua) <= 1e-10 * max(1.0, abs(supplied))
    with pytest.raises(ModelError) as info:
        flexkane.loads_model(SPATIAL_GEARED.format(law="q_waist + 0.1*q_shoulder"))
    assert info.value.path == "joints.shoulder.driver.coordinate" and "its own coordinate" in str(info.value)


#: SPATIAL_GEARED with a spherical waist (Euler parameters q_waist_e0..e3, no torque).
SOCKET_GEARED = SPATIAL_GEARED.replace('type = "revolute"\nparent = "ground"', 'type = "spherical"\nparent = "ground"') \
    .replace('axis = [0, 0, 1]\ntorque = "0.3*sin(t)"\n', "")


def test_a_law_of_euler_parameters_keeps_the_energy_balance():
    """A shoulder following the Euler parameter e1 of the spherical waist that carries its link (and t):
    the driven speed is the law's rate through the Euler parameters' kinematic equations, and
    d(energy)/dt = power_nonconservative at random states (unit Euler parameters)."""
    eom = flexkane.derive(flexkane.loads_model(SOCKET_GEARED.format(law="2*q_waist_e1 + 0.1*sin(t)")))
    assert eom.state_names == ["q_waist_e0", "q_waist_e1", "q_waist_e2", "q_waist_e3", "u_waist_wx", "u_waist_wy",
                               "u_waist_wz"]
    balance = _energy_balance(eom)
    rng = np.random.default_rng(3)
    for _ in range(3):
        e = rng.normal(size=4)
        de, supplied = balance([*(e / np.linalg.norm(e)), *rng.uniform(-2.0, 2.0, 3), rng.uniform(0.0, 3.0)])
        assert abs(supplied) > 1e-3 and abs(de - supplied) <= 1e-10 * max(1.0, abs(de))


def test_linearize_with_a_spatial_gear_reduces_the_driven_coordinate():
    """The spatial gear hanging at rest (b below the shoulder, q_waist = -pi): the linear model's states
    are (q_waist, u_waist), and A equals the finite-difference Jacobian of the nonlinear right-hand side."""
    from flexkane import linearize

    text = SPATIAL_GEARED.format(law="c*q_waist").replace('torque = "0.3*sin(t)"\n', "")
    model = flexkane.loads_model(text + "\n[initial]\nq_waist = -3.0\n")
    linear = linearize(model, about="equilibrium")
    A, _ = linear.state_space()
    assert linear.state_names == ["q_waist", "u_waist"] and abs(float(linear.q0[0]) + np.pi) <= 1e-8
    accelerations = _flexkane_accelerations(flexkane.derive(model))

    def rhs(x):
        return np.array([x[1], accelerations(x[0], x[1], 0.0)])

    J = _finite_difference_jacobian(rhs, np.array([float(linear.q0[0]), 0.0]))
    assert J[1, 0] < 0 and np.max(np.abs(A - J)) <= 1e-7 * np.max(np.abs(J))


@pytest.mark.parametrize("text", [
    GEARED.format(law="c*q_sa + 0.25*tip_y + 0.1*sin(2*t)") + '\n[sensors.tip_y]\ntype = "position"\nbody = "a"\n'
    'point = "tip"\ncomponent = "y"\n',
    GEARED_BEAM.replace("c*q_sa + 0.1*sin(3*t)", "c*q_sa + 0.1*sin(3*t) + 0.2*q_link_1"),
    TWO_DRIVERS,
    GEARED.format(law="c*q_sa + z_f") + FILTER,
    GEARED.format(law="-2*(q_sb - c*q_sa) + 0.3*cos(t)").replace("coordinate =", "speed ="),
], ids=["gear-and-cam", "geared-beam", "two-drivers", "filtered-reference", "velocity-servo"])
def test_planar_drivers_of_the_state_through_the_spatial_engine_give_the_planar_equations(text):
    """Each planar model of this file with drivers of the state (a law reading a sensor, a beam's modal
    coordinate renamed by as_spatial, a tip-deflection sensor, a controller state, a speed law) and
    its spatial form: the same states, M, f and controller rates at random states, to 1e-10."""
    from flexkane.model import as_spatial
    from spatial_models import compact_system

    planar = flexkane.loads_model(text)
    eom2, eom3 = flexkane.derive(planar), flexkane.derive(as_spatial(planar))
    assert [n.replace("_y", "_") for n in eom3.state_names] == eom2.state_names
    system2, system3 = compact_system(eom2), compact_system(eom3)
    rng = np.random.default_rng(2)
    for _ in range(3):
        q, u, z = (rng.uniform(-1.0, 1.0, len(x)) for x in (eom2.q, eom2.u, eom2.z))
        t = rng.uniform(0.0, 2.0)
        for a, b in zip(system2(q, u, z, t), system3(q, u, z, t)):
            assert np.abs(b - a).max(initial=0.0) <= 1e-10 * max(1.0, np.abs(a).max(initial=0.0))


def _kanes_method_free_chain():
    """M(qa, qb) and f(qa, qb, ua, ub) of the two-link chain without constraint, by KanesMethod."""
    t = dynamicsymbols._t
    qa, qb, ua, ub = dynamicsymbols("qa qb ua ub")
    N = ReferenceFrame("N")
    A = N.orientnew("A", "Axis", (qa, N.z))
    B = A.orientnew("B", "Axis", (qb, A.z))
    A.set_ang_vel(N, ua * N.z)
    B.set_ang_vel(A, ub * A.z)
    O = Point("O")
    O.set_vel(N, 0)
    Ac = O.locatenew("Ac", 0.4 * A.x)
    Ac.v2pt_theory(O, N, A)
    hinge = O.locatenew("H", 0.8 * A.x)
    hinge.v2pt_theory(O, N, A)
    Bc = hinge.locatenew("Bc", 0.3 * B.x)
    Bc.v2pt_theory(hinge, N, B)
    bodies = [RigidBody("a", Ac, A, 1.0, (inertia(A, 0, 0, 0.05), Ac)),
              RigidBody("b", Bc, B, 0.7, (inertia(B, 0, 0, 0.03), Bc))]
    kane = KanesMethod(N, q_ind=[qa, qb], u_ind=[ua, ub], kd_eqs=[qa.diff(t) - ua, qb.diff(t) - ub])
    kane.kanes_equations(bodies, [(Ac, -9.81 * N.y), (Bc, -0.7 * 9.81 * N.y)])
    X = sp.symbols("QA QB UA UB")
    plain = dict(zip([qa, qb, ua, ub], X))
    return tuple(sp.lambdify(X, e.xreplace(plain), "numpy", cse=True) for e in (kane.mass_matrix, kane.forcing))


def test_a_speed_law_of_the_state_is_a_velocity_servo():
    """u_sb = -2 (q_sb - c q_sa) + 0.3 cos(t): q_sb stays in the state, the driver's effort acts on sb
    alone, and KanesMethod's free chain with u_sb' = dL/dt gives the same u_sa' and the same effort
    (the residual of sb's row) at random states, to 1e-10."""
    law = "-2*(q_sb - c*q_sa) + 0.3*cos(t)"
    eom = flexkane.derive(flexkane.loads_model(GEARED.format(law=law).replace("coordinate =", "speed =")))
    assert eom.state_names == ["q_sa", "q_sb", "u_sa"]
    values = eom.constant_values()
    args = [*eom.q, *eom.u, eom.t]
    ud = sp.Symbol("a")
    M, f, effort = (sp.lambdify([*args, ud], eom.expand(e).xreplace(values).xreplace({eom.ud[0]: ud}), "numpy",
                                cse=True)
                    for e in (eom.compact.mass_matrix[0, 0], eom.compact.forcing[0], eom.compact.outputs["effort_sb"]))
    rate_q_sb = sp.lambdify(args, eom.expand(eom.compact.qdot[1]).xreplace(values), "numpy")
    M_ref, f_ref = _kanes_method_free_chain()
    rng = np.random.default_rng(5)
    for qa, qb, ua, t in rng.uniform(-2.0, 2.0, size=(5, 4)):
        ours = f(qa, qb, ua, t, 0.0) / M(qa, qb, ua, t, 0.0)
        ub = -2 * (qb - 0.5 * qa) + 0.3 * np.cos(t)
        ub_rate = -2 * (ub - 0.5 * ua) - 0.3 * np.sin(t)
        assert abs(rate_q_sb(qa, qb, ua, t) - ub) <= 1e-14
        Mk, fk = np.atleast_2d(M_ref(qa, qb, ua, ub)), np.ravel(f_ref(qa, qb, ua, ub))
        expected = (fk[0] - Mk[0, 1] * ub_rate) / Mk[0, 0]
        assert abs(ours - expected) <= 1e-10 * max(1.0, abs(expected))
        torque = Mk[1, 0] * expected + Mk[1, 1] * ub_rate - fk[1]
        assert abs(effort(qa, qb, ua, t, ours) - torque) <= 1e-10 * max(1.0, abs(torque))


def test_linearize_refuses_a_speed_law_of_the_state_by_name():
    from flexkane import linearize

    model = flexkane.loads_model(GEARED.format(law="-2*(q_sb - c*q_sa)").replace("coordinate =", "speed ="))
    with pytest.raises(ModelError) as info:
        linearize(model)
    assert info.value.path == "joints.sb.driver.speed" and "coordinate" in str(info.value)


def test_a_driver_law_with_a_saturated_output_is_refused_by_name():
    """A saturated controller output has a step in its derivative: the driven acceleration would not exist."""
    text = GEARED.format(law="c*q_sa + k") + '\n[controllers.k]\noutput = "q_sa"\nmax = 0.2\n'
    with pytest.raises(ModelError) as info:
        flexkane.derive(flexkane.loads_model(text))
    assert info.value.path == "joints.sb.driver.coordinate" and "steps or impulses" in str(info.value)


def test_the_drivers_reduction_is_a_value_the_equations_take_once():
    """The reduction by a gear's law (kane.driver_laws.reduce_by_drivers) leaves its inputs unchanged,
    gives the same value twice, and every attribute of the equations is set once."""
    import dataclasses

    from flexkane.kane.driver_laws import DriverReduction, reduce_by_drivers
    from reduction_recording import derive_recording

    eom, calls = derive_recording(flexkane.loads_model(GEARED.format(law="c*q_sa")), "reduce_by_drivers",
                                  reduce_by_drivers)
    assert {name: n for name, n in eom.writes.items() if n > 1} == {}
    assert eom.writes["mass_matrix"] == eom.writes["forcing"] == eom.writes["u"] == 1
    [(args, kwargs, before, result)] = calls
    for given, copy in zip(args, before):
        if copy is not None:
            assert given == copy
    assert reduce_by_drivers(*args, **kwargs) == result
    assert isinstance(result, DriverReduction)
    with pytest.raises(dataclasses.FrozenInstanceError):
        result.forcing = None
    assert eom.compact.mass_matrix == result.mass_matrix and eom.compact.forcing == result.forcing
    # P^T M P over the one free speed is the second derivative of the kinetic energy with u_sb = c u_sa
    [u] = eom.u
    values = {k: sp.Float(v) for k, v in eom.constant_values().items()}
    mass = eom.expand(result.mass_matrix[0, 0]).xreplace(values)
    kinetic = sp.diff(eom.expand(eom.compact.outputs["kinetic"]), u, 2).xreplace(values)
    for q in (-1.1, 0.3, 2.0):
        at = {eom.q[0]: q, eom.t: 0.0}
        assert abs(float(mass.subs(at)) - float(kinetic.subs(at))) <= 1e-12
