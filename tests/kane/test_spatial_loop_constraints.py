"""Closed loops in spatial chains: spherical, point_on_line and weld loop constraints.

Oracles: the closed-form kinematics of the mechanisms (a point held on a line, the input-output
relation of the RSSR four-bar), the conservation of energy of unforced, undamped loops (its rate
along the reduced equations is zero at any closed state; over a run it stays at solver tolerance),
the constraints (their rate is zero; over a run they stay at solver tolerance), and the planar
engine (planar loops through ``as_spatial``, to 1e-10).
"""

import pathlib

import numpy as np
import pytest

import flexkane
from flexkane.errors import ModelError
from flexkane.model import loads_model
from flexkane.model.as_spatial import as_spatial
from spatial_models import accelerations, output_rates

HERE = pathlib.Path(__file__).parent / "spatial_loops"


def _quaternion_matrix(e):
    """Direction cosines of unit Euler parameters (independent of the engine's)."""
    e0, e1, e2, e3 = e
    return np.array([[1 - 2 * (e2 ** 2 + e3 ** 2), 2 * (e1 * e2 - e0 * e3), 2 * (e1 * e3 + e0 * e2)],
                     [2 * (e1 * e2 + e0 * e3), 1 - 2 * (e1 ** 2 + e3 ** 2), 2 * (e2 * e3 - e0 * e1)],
                     [2 * (e1 * e3 - e0 * e2), 2 * (e2 * e3 + e0 * e1), 1 - 2 * (e1 ** 2 + e2 ** 2)]])


def _product(a, b):
    a0, av, b0, bv = a[0], np.asarray(a[1:]), b[0], np.asarray(b[1:])
    return np.concatenate([[a0 * b0 - av @ bv], a0 * bv + b0 * av + np.cross(av, bv)])


@pytest.fixture(scope="module")
def axis_pendulum():
    model = flexkane.load_model(HERE / "axis_pendulum.toml")
    return model, flexkane.derive(model, cache=False)


def test_dependent_angular_speeds_close_the_loop_on_the_unit_sphere(axis_pendulum):
    """The two dependent speeds are angular speeds of the spherical joint (chosen by pivoting, as in
    the plane); closing the initial state moves the Euler parameters along them: P lands on the line
    at [d, sqrt(l^2 - d^2), 0], the parameters stay of unit norm."""
    model, eom = axis_pendulum
    assert [u.name for u in eom.u] == ["u_pivot_wx"]
    assert [u.name for u in eom.dependent_speeds] == ["u_pivot_wy", "u_pivot_wz"]
    y = eom.initial_state(model)
    e = y[:4]
    assert abs(np.linalg.norm(e) - 1) <= 1e-14
    P = _quaternion_matrix(e) @ np.array([0.5, 0.0, 0.0])     # OP in N
    assert np.abs(P - [0.3, 0.4, 0.0]).max() <= 1e-12, P


def test_closure_turns_the_spherical_joint_only_about_its_dependent_axes(axis_pendulum):
    """The closure moves the Euler parameters along the dependent angular speeds w_y, w_z only: the
    turn from the given orientation to the closed one has no component about the body's x axis (the
    independent speed's), and P lands on the line."""
    model, eom = axis_pendulum
    given = np.array([np.cos(0.25), 0.0, 0.0, np.sin(0.25)])    # a guess: 0.5 rad about z
    e = eom.project_coordinates(given.copy(), eom.constant_values())
    turn = _product(given * [1, -1, -1, -1], e)
    assert abs(turn[1]) <= 1e-15 and np.abs(turn[2:]).max() > 0.05, turn
    assert abs(np.linalg.norm(e) - 1) <= 1e-15
    P = _quaternion_matrix(e) @ np.array([0.5, 0.0, 0.0])
    assert np.abs(P - [0.3, 0.4, 0.0]).max() <= 1e-12, P


def _closed_states(model, eom, count=3):
    """Closed states: the initial one turned about the fixed axis OP, with several speeds."""
    y0 = eom.initial_state(model)
    e0 = y0[:4]
    axis = _quaternion_matrix(e0) @ np.array([1.0, 0.0, 0.0])
    rng = np.random.default_rng(5)
    for _ in range(count):
        beta = rng.uniform(-2.0, 2.0)
        turn = np.concatenate([[np.cos(beta / 2)], np.sin(beta / 2) * axis])
        yield _product(turn, e0), rng.uniform(-3.0, 3.0, len(eom.u))


def test_reduced_equations_keep_energy_and_constraints(axis_pendulum):
    """Along the reduced equations (u_d eliminated, e' = 1/2 E(e) w with the dependent w's), the
    rates of the energy and of the constraints are zero at closed states (the kinetic energy's is
    not: the plate swings)."""
    model, eom = axis_pendulum
    names = ("energy", "kinetic", "constraint_line_1", "constraint_line_2")
    rates = output_rates(eom, names, list(_closed_states(model, eom)))
    scale = np.abs(rates[:, 1]).max()
    assert scale > 0.1
    assert np.abs(rates[:, 0]).max() <= 1e-9 * scale, rates
    assert np.abs(rates[:, 2:]).max() <= 1e-9, rates


def test_singular_constraints_at_the_initial_state_are_refused(axis_pendulum):
    """Redundant constraints (P held at a ground point at its own distance from the pivot: rank 2 of
    3) and given dependent speeds that cannot be solved for (w_x does not move P) are ModelErrors."""
    model, _ = axis_pendulum
    redundant = model.copy()
    line = redundant.constraints["line"]
    line.type, line.axis, line.position_a = "spherical", 0, (0.3, 0.4, 0.0)
    with pytest.raises(ModelError, match=r"constraints: expected independent loop constraints.*rank 2"):
        flexkane.derive(redundant.validate(), cache=False)
    unsolvable = model.copy()
    unsolvable.constraints["line"].dependent = ["u_pivot_wx", "u_pivot_wy"]
    with pytest.raises(ModelError, match=r"constraints.dependent: .*u_pivot_wx"):
        flexkane.derive(unsolvable.validate(), cache=False)


TRAMMEL = """
name = "trammel"
description = "Elliptic trammel: two sliders on perpendicular guides joined by a bar"
[bodies.a]
mass = 0.4
inertia = 0.001
[bodies.bar]
mass = 1.0
inertia = 0.02
points = { A = [-0.25, 0.0], B = [0.25, 0.0] }
[bodies.b]
mass = 0.3
inertia = 0.001
[joints.guide_x]
type = "prismatic"
parent = "ground"
child = "a"
[joints.hinge]
type = "revolute"
parent = "a"
child = "bar"
child_point = "A"
[joints.guide_y]
type = "prismatic"
parent = "ground"
child = "b"
axis = 1.5707963267948966
[constraints.pin]
type = "revolute"
body_a = "bar"
point_a = "B"
body_b = "b"
[gravity]
g = 9.81
direction = [0, -1]
[initial]
q_hinge = 2.2
u_hinge = 1.5
q_guide_x = 0.3
q_guide_y = 0.4
"""


def test_planar_loop_through_the_spatial_engine_equals_the_planar_engine():
    """The trammel's reduced accelerations from both engines at closed states agree to 1e-10 (the
    planar revolute loop joint as a point_on_line along z)."""
    planar = loads_model(TRAMMEL)
    spatial = as_spatial(planar)
    eom2, eom3 = flexkane.derive(planar, cache=False), flexkane.derive(spatial, cache=False)
    assert [u.name for u in eom3.u] == [u.name for u in eom2.u] == ["u_hinge"]
    assert list(eom3.dependent_speeds) == list(eom2.dependent_speeds)
    a2, a3 = accelerations(eom2), accelerations(eom3)
    names = [q.name for q in eom2.q]
    for angle, rate in ((2.2, 1.5), (0.4, -2.0), (3.5, 0.7)):
        q = eom2.initial_state(planar)[: len(names)]
        q[names.index("q_hinge")] = angle
        q2 = eom2.project_coordinates(q, eom2.constant_values())
        q3 = eom3.project_coordinates(q.copy(), eom3.constant_values())
        assert np.abs(q3 - q2).max() <= 1e-12
        u = np.array([rate])
        assert np.abs(a3(q3, u) - a2(q2, u)).max() <= 1e-10 * max(1.0, np.abs(a2(q2, u)).max())


# ---------------------------------------------------------------------- runs (compiled models)
def _run(model, t_end, rtol=1e-10, atol=1e-12):
    eom = flexkane.derive(model, cache=False)
    return flexkane.simulate(flexkane.compile_model(eom), t_end=t_end, dt_out=t_end / 100, rtol=rtol, atol=atol)


def rssr_output_angle(crank, a=0.1, b=0.4, c=0.25, p=(0.2, 0.1, 0.2)):
    """The rocker angle of the RSSR four-bar of rssr.toml from its crank angle (closed form).

    The crank tip A = a (cos t, sin t, 0), the rocker tip B = p + c (0, cos f, sin f); |B - A| = b
    gives P cos f + Q sin f = R (the branch of the model's initial state)."""
    px, py, pz = p
    P = -2 * c * (a * np.sin(crank) - py)
    Q = 2 * pz * c
    R = b ** 2 - (a * np.cos(crank) - px) ** 2 - (a * np.sin(crank) - py) ** 2 - c ** 2 - pz ** 2
    return np.arctan2(Q, P) - np.arccos(R / np.hypot(P, Q))


@pytest.mark.slow
def test_rssr_four_bar_follows_its_closed_form_and_conserves_energy():
    """The spatial RSSR four-bar swinging under gravity for 1 s (the crank turns through more than
    5 rad): the rocker angle equals the closed-form input-output relation to 1e-8, the loop stays
    closed and the energy constant to the solver's tolerance."""
    model = flexkane.load_model(HERE / "rssr.toml")
    run = _run(model, 1.0)
    state = {name: run.state[:, k] for k, name in enumerate(run.state_names)}
    assert np.ptp(state["q_crank"]) > 5.0
    assert np.abs(state["q_rocker"] - rssr_output_angle(state["q_crank"])).max() <= 1e-8
    closure = max(np.abs(run.outputs[f"constraint_loop_{k}"]).max() for k in (1, 2, 3))
    assert closure <= 1e-9, closure
    energy = run.outputs["energy"]
    assert np.ptp(energy) <= 1e-8 * np.ptp(run.outputs["kinetic"]), np.ptp(energy)


@pytest.mark.slow
@pytest.mark.parametrize("name, t_end", [("four-bar", 2.0), ("slider-crank", 0.02)])
def test_planar_loops_through_the_spatial_engine_give_the_planar_results(name, t_end):
    """The rigid four-bar and the flexible slider-crank (an elastic rod in a closed loop, its crank
    driven) run by both engines: coordinates and energies agree to 1e-10 (relative to their range)."""
    planar = flexkane.builtin_model(name)
    runs = [_run(m, t_end, 1e-12, 1e-13) for m in (planar, as_spatial(planar))]
    modal = {f"{x}_rod_{i}": f"{x}_rod_y{i}" for i in (1, 2) for x in "qu"}
    for k, column in enumerate(runs[0].state_names):
        a = runs[0].state[:, k]
        b = runs[1].state[:, runs[1].state_names.index(modal.get(column, column))]
        assert np.abs(b - a).max() <= 1e-10 * max(1.0, np.abs(a).max()), column
    for output in ("kinetic", "energy"):
        a, b = runs[0].outputs[output], runs[1].outputs[output]
        assert np.abs(b - a).max() <= 1e-10 * max(1.0, np.abs(a).max()), output


@pytest.mark.slow
def test_flexible_spatial_slider_crank_keeps_its_loop_closed_and_its_energy_balance():
    """The flexible spatial slider-crank (driven crank, elastic rod on a universal joint, raised
    slider, spherical closure) for 0.5 s: the loop stays closed to solver tolerance, the driver's work
    equals the change of the energy (kinetic + strain), and the slider stays within the rod's small
    deflection of the rigid mechanism's closed-form travel a cos(t) + sqrt(L^2 - h^2 - a^2 sin(t)^2)."""
    model = flexkane.load_model(HERE / "spatial_slider_crank.toml")
    run = _run(model, 0.5)
    closure = max(np.abs(run.outputs[f"constraint_piston_{k}"]).max() for k in (1, 2, 3))
    assert closure <= 1e-9, closure
    energy = run.outputs["energy"]
    assert np.ptp(run.outputs["strain"]) > 1e-4 and np.ptp(energy) > 0.1
    assert np.abs(run.outputs["energy_balance"]).max() <= 1e-8 * np.ptp(energy)
    crank = 10.0 * run.t
    rigid = 0.15 * np.cos(crank) + np.sqrt(0.3 ** 2 - 0.05 ** 2 - (0.15 * np.sin(crank)) ** 2)
    slider = run.state[:, run.state_names.index("q_slider")]
    assert np.abs(slider - rigid).max() <= 1e-4


@pytest.mark.slow
def test_welded_pair_moves_as_one_body_and_conserves_energy():
    """A body on a free joint welded to a pendulum (six scalar constraints, the free joint's six
    speeds dependent): its frame stays at the pendulum's turned by the weld's orientation, and the
    energy is constant to solver tolerance over 1 s."""
    model = flexkane.load_model(HERE / "welded_pair.toml")
    run = _run(model, 1.0)
    state = {name: run.state[:, k] for k, name in enumerate(run.state_names)}
    n = np.array([1.0, 1.0, 0.0]) / np.sqrt(2.0)
    for k in (0, 50, 100):
        angle = state["q_hinge"][k]
        arm = np.concatenate([[np.cos(angle / 2)], np.sin(angle / 2) * n])
        weld = np.array([np.cos(0.2), 0.0, np.sin(0.2), 0.0])
        expected = _product(arm, weld)
        e = np.array([state[f"q_float_e{i}"][k] for i in range(4)])
        assert min(np.abs(e - expected).max(), np.abs(e + expected).max()) <= 1e-9
    closure = max(np.abs(run.outputs[f"constraint_glue_{k}"]).max() for k in range(1, 7))
    assert closure <= 1e-9, closure
    energy = run.outputs["energy"]
    assert np.ptp(run.outputs["kinetic"]) > 0.01
    assert np.ptp(energy) <= 1e-8 * np.ptp(run.outputs["kinetic"]), np.ptp(energy)
