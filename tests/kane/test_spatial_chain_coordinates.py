"""Coordinates and speeds of spatial chains: Euler parameters without a speed of their own, so more
coordinates than speeds; sequential naming; drivers; the kinematic equations of each joint type."""

import numpy as np
import sympy as sp

import flexkane
from flexkane.kane.chain import build_chain
from flexkane.model import loads_model

CHAIN = """
dimensions = 3
naming = "{naming}"

[bodies.A]
mass = 1.0
inertia = [0.1, 0.2, 0.3]
[bodies.B]
mass = 1.0
inertia = [0.1, 0.2, 0.3]
[bodies.C]
mass = 1.0
inertia = [0.1, 0.2, 0.3]

[joints.j1]
type = "free"
parent = "ground"
child = "A"
[joints.j2]
type = "revolute"
parent = "A"
child = "B"
axis = [0, 0, 1]
{driver}
[joints.j3]
type = "spherical"
parent = "B"
child = "C"
"""


def test_euler_parameters_give_more_coordinates_than_speeds():
    eom = flexkane.derive(loads_model(CHAIN.format(naming="joint", driver="")), cache=False)
    assert [q.name for q in eom.q] == ["q_j1_x", "q_j1_y", "q_j1_z", "q_j1_e0", "q_j1_e1", "q_j1_e2", "q_j1_e3",
                                       "q_j2", "q_j3_e0", "q_j3_e1", "q_j3_e2", "q_j3_e3"]
    assert [u.name for u in eom.u] == ["u_j1_vx", "u_j1_vy", "u_j1_vz", "u_j1_wx", "u_j1_wy", "u_j1_wz", "u_j2",
                                       "u_j3_wx", "u_j3_wy", "u_j3_wz"]
    assert eom.qdot.shape == (12, 1) and eom.mass_matrix.shape == (10, 10)
    assert np.array_equal(eom.initial_state()[:12], [0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0])


def test_sequential_names_number_coordinates_and_speeds_separately():
    eom = flexkane.derive(loads_model(CHAIN.format(naming="sequential", driver="")), cache=False)
    assert [q.name for q in eom.q] == [f"q{k}" for k in range(1, 13)]
    assert [u.name for u in eom.u] == [f"u{k}" for k in range(1, 11)]


def test_euler_parameter_kinematics_keep_the_norm_and_give_the_angular_velocity():
    chain = build_chain(loads_model(CHAIN.format(naming="joint", driver="")).validate())
    e = [c.q for c in chain.of("j3")]
    w = [c.u for c in chain.of("j3")[1:]]
    rates = [chain.qdot[x] for x in e]
    assert sp.expand(sum(x * r for x, r in zip(e, rates))) == 0          # d|e|^2/dt = 0
    # free joint: the translation rates are the velocity along J_c's axes turned into J_p
    x = [c.q for c in chain.of("j1")[:3]]
    assert all(chain.qdot[xk].has(chain.of("j1")[0].u) for xk in x)
    assert all(r.free_symbols <= set(e) | set(w) for r in rates)


def test_a_driven_revolute_joint_leaves_the_state_and_reports_its_effort():
    driver = 'driver = { coordinate = "0.5*sin(t)" }'
    eom = flexkane.derive(loads_model(CHAIN.format(naming="joint", driver=driver)), cache=False)
    assert "q_j2" not in [q.name for q in eom.q] and "u_j2" not in [u.name for u in eom.u]
    assert len(eom.q) == 11 and len(eom.u) == 9
    assert "effort_j2" in eom.output_names


def test_a_planar_joint_normal_given_by_expressions_is_refused_with_its_path():
    import pytest

    from flexkane.errors import ModelError

    text = CHAIN.format(naming="joint", driver="").replace('type = "spherical"', 'type = "planar"\naxis = ["a", 0, 1]')
    model = loads_model(text + "\n[parameters]\na = 0.5\n")
    with pytest.raises(ModelError) as info:
        flexkane.derive(model, cache=False)
    assert info.value.path == "joints.j3.axis"
