"""A planar chain derived by the spatial engine (``as_spatial``: z normal, motion in the x-y plane)
gives the planar engine's accelerations to 1e-10; so does every planar built-in model, its mass
matrix and forcing compared at random states (the notebook variant's midpoint gravity and
shear-moment forces, drivers whose law reads the state, closed loops and controllers included).

The chain has a free joint (the spatial ``planar`` joint), a revolute joint with a spring, a damper,
an actuator torque and a constant angle, a prismatic joint along a turned axis with a spring, a weld,
gravity, a load with a force in local axes and a torque, and a spring between a ground point and a
body point. The planar free joint's speeds are velocity components along the child's axes (eq.
8.10), the spatial planar joint's the rates of x and y: the test maps one to the other.
"""

import numpy as np
import pytest
import sympy as sp

import flexkane
from flexkane.builtin import builtin_model, builtin_names
from flexkane.model import loads_model
from flexkane.model.as_spatial import as_spatial
from flexkane.model.coordinates import coordinate_names
from flexkane.model.field_values import FieldValues
from spatial_models import accelerations, compact_system

PLANAR = """
name = "planar-rigid"

[bodies.carrier]
mass = 3.0
inertia = 0.4
points = { P = [0.3, 0.1], C = [-0.1, 0.05] }

[bodies.arm]
mass = 1.2
inertia = 0.08
points = { root = [-0.25, 0.0], end = [0.25, 0.02] }

[bodies.slide]
mass = 0.5
inertia = 0.01
points = { S = [0.05, 0.0] }

[bodies.tipmass]
mass = 0.3
inertia = 0.002
points = { T = [0.02, 0.01] }

[joints.float]
type = "free"
parent = "ground"
child = "carrier"
child_point = "C"
parent_position = [0.1, 0.2]
angle = 0.2

[joints.hinge]
type = "revolute"
parent = "carrier"
child = "arm"
parent_point = "P"
child_point = "root"
angle = 0.3
stiffness = 4.0
damping = 0.3
rest = 0.1
torque = "0.5*sin(3*t)"

[joints.slider]
type = "prismatic"
parent = "arm"
child = "slide"
parent_point = "end"
axis = 0.4
stiffness = 20.0

[joints.tip]
type = "weld"
parent = "slide"
child = "tipmass"
parent_point = "S"
child_point = "T"
angle = 0.1

[gravity]
g = 9.81
direction = [0, -1]

[loads.push]
body = "arm"
point = "end"
force = [1.0, "cos(t)"]
torque = 0.5
frame = "local"

[springs.tether]
body_a = "ground"
position_a = [0.0, 1.0]
body_b = "tipmass"
point_b = "T"
stiffness = 15.0
damping = 0.2
rest_length = 0.5
"""


def test_planar_chain_through_the_spatial_engine_equals_the_planar_engine():
    planar = loads_model(PLANAR)
    spatial = as_spatial(planar)
    eom2 = flexkane.derive(planar, cache=False)
    eom3 = flexkane.derive(spatial, cache=False)
    assert [q.name for q in eom3.q] == [q.name for q in eom2.q]
    assert [u.name for u in eom3.u] == [u.name for u in eom2.u]
    a2, a3 = accelerations(eom2), accelerations(eom3)
    names = [q.name for q in eom2.q]
    ix, iy, ia = (names.index(f"q_float_{r}") for r in ("x", "y", "angle"))
    rng = np.random.default_rng(3)
    for _ in range(5):
        q = rng.uniform(-1.0, 1.0, len(names))
        u = rng.uniform(-2.0, 2.0, len(names))
        t = rng.uniform(0.0, 2.0)
        # the spatial planar joint's speeds are the rates of x and y
        angle = q[ia] + 0.2
        c, s = np.cos(angle), np.sin(angle)
        u3 = u.copy()
        u3[ix], u3[iy] = c * u[ix] - s * u[iy], s * u[ix] + c * u[iy]
        ud2, ud3 = a2(q, u, t), a3(q, u3, t)
        expected = ud2.copy()
        expected[ix] = c * ud2[ix] - s * ud2[iy] - u3[iy] * u[ia]
        expected[iy] = s * ud2[ix] + c * ud2[iy] + u3[ix] * u[ia]
        assert np.abs(ud3 - expected).max() <= 1e-10 * max(1.0, np.abs(expected).max())
    # the outputs both engines have agree at a state too (energies, positions, momentum)
    values2, values3 = eom2.constant_values(), eom3.constant_values()
    state2 = {s: v for s, v in zip(eom2.q + eom2.u, np.concatenate([q, u]))}
    state3 = {s: v for s, v in zip(eom3.q + eom3.u, np.concatenate([q, u3]))}
    for name in ("kinetic", "potential_gravity", "potential_springs", "x_arm", "y_tipmass", "p_x", "p_y", "x_cm"):
        o2 = float(eom2.outputs[name].xreplace({**values2, **state2, eom2.t: t}))
        o3 = float(eom3.outputs[name].xreplace({**values3, **state3, eom3.t: t}))
        assert abs(o3 - o2) <= 1e-10 * max(1.0, abs(o2)), name


@pytest.mark.slow
def test_planar_chain_through_the_spatial_engine_gives_the_same_results():
    """Both engines compiled and run at tight tolerance: positions, energies and the work of the
    non-conservative forces agree to 1e-10 (relative to their range) over 2 s."""
    planar = loads_model(PLANAR).with_values({"u_float_x": 0.3, "u_float_angle": 1.0, "u_hinge": -0.5})
    runs = [flexkane.simulate(flexkane.compile_model(flexkane.derive(m, cache=False)), t_end=2.0, dt_out=0.02,
                              rtol=1e-13, atol=1e-13) for m in (planar, as_spatial(planar))]
    for name in ("x_arm", "y_arm", "x_tipmass", "y_tipmass", "kinetic", "energy", "work"):
        a, b = runs[0].outputs[name], runs[1].outputs[name]
        assert np.abs(b - a).max() <= 1e-10 * max(1.0, np.abs(a).max()), name


#: Every planar built-in model.
PLANAR_BUILTINS = [name for name in builtin_names() if builtin_model(name).dimensions == 2]


def _spatial_name(planar, name: str) -> str:
    """The spatial model's name of a planar coordinate or speed (modal ones get the plane y)."""
    if planar.naming == "sequential":
        return name
    modal = {n: f"{p}_{c.owner}_y{c.index}" for c in coordinate_names(planar) if c.role == "mode"
             for n, p in ((c.q, "q"), (c.u, "u"))}
    return modal.get(name, name)


def _free_joint_speeds(planar, eom2, q, u):
    """``T`` and ``c`` of the planar free joints' speeds ``u2 = T u3`` (components along the child's axes
    from the rates of x and y, eq. 8.10) and ``c = T' u3`` at a state (q, u2)."""
    names = [x.name for x in eom2.u]
    q_names = [x.name for x in eom2.q]
    T, c = np.eye(len(u)), np.zeros(len(u))
    fields = FieldValues(planar)
    for joint in planar.joints.values():
        if joint.type != "free":
            continue
        cx, cy, ca = (x for x in coordinate_names(planar) if x.owner == joint.name)
        ix, iy, ia = (names.index(x.u) for x in (cx, cy, ca))
        phi = q[q_names.index(ca.q)] + fields.value(joint.angle, f"joints.{joint.name}.angle")
        cos, sin = np.cos(phi), np.sin(phi)
        T[np.ix_([ix, iy], [ix, iy])] = [[cos, sin], [-sin, cos]]
        c[ix], c[iy] = u[ia] * u[iy], -u[ia] * u[ix]
    return T, c


def _random_states(planar, eom2, rng, count):
    """``count`` states (q, u, z, t) of the planar equations; closed loops closed by projection."""
    states = []
    values = eom2.constant_values()
    for _ in range(count):
        t = rng.uniform(0.0, 0.5)
        u = rng.uniform(-1.0, 1.0, len(eom2.u))
        z = rng.uniform(-0.5, 0.5, len(eom2.z))
        if planar.constraints:    # near the initial state, where the loops close
            q = eom2.initial_state(planar)[: len(eom2.q)] + rng.uniform(-0.02, 0.02, len(eom2.q))
            q = eom2.project_coordinates(q, values, t)
        else:
            q = rng.uniform(-0.5, 0.5, len(eom2.q))
        states.append((q, u, z, t))
    return states


@pytest.mark.parametrize("name", PLANAR_BUILTINS)
def test_every_planar_builtin_through_the_spatial_engine_has_the_planar_mass_matrix_and_forcing(name):
    """Each planar built-in model and its spatial form (as_spatial) derived by the spatial engine:
    ``M3 = T^T M2 T`` and ``f3 = T^T (f2 - M2 T' u3)`` at random states, to 1e-10 (``u2 = T u3``: the
    identity but for the speeds of planar free joints), and the same controller rates."""
    planar = builtin_model(name)
    spatial = as_spatial(planar)
    eom2, eom3 = flexkane.derive(planar, cache=False), flexkane.derive(spatial, cache=False)
    for two, three in ((eom2.q, eom3.q), (eom2.u, eom3.u), (eom2.z, eom3.z)):
        assert [_spatial_name(planar, x.name) for x in two] == [x.name for x in three]
    system2, system3 = compact_system(eom2), compact_system(eom3)
    rng = np.random.default_rng(26)
    for q, u, z, t in _random_states(planar, eom2, rng, 3):
        if planar.constraints:     # the spatial loop closes at the same coordinates
            q3 = eom3.project_coordinates(q.copy(), eom3.constant_values(), t)
            assert np.abs(q3 - q).max() <= 1e-12
        T, c = _free_joint_speeds(planar, eom2, q, u)
        u3 = np.linalg.solve(T, u)
        M2, f2, z2 = system2(q, u, z, t)
        M3, f3, z3 = system3(q, u3, z, t)
        assert np.abs(M2).max() > 0 and np.abs(f2).max() > 0
        expected_M, expected_f = T.T @ M2 @ T, T.T @ (f2 - M2 @ c)
        assert np.abs(M3 - expected_M).max() <= 1e-10 * max(1.0, np.abs(expected_M).max())
        assert np.abs(f3 - expected_f).max() <= 1e-10 * max(1.0, np.abs(expected_f).max())
        assert np.abs(z3 - z2).max(initial=0.0) <= 1e-10 * max(1.0, np.abs(z2).max(initial=0.0))


def test_the_notebook_beam_bending_in_its_z_plane_turned_into_the_motion_equals_the_planar_engine():
    """falling-beam (midpoint weight, shear-moment forces) with its beam's mode in the z family and
    the principal axes turned by -pi/2 (z_p along the frame's y: the z plane is the plane of the
    motion): the formulas of the z plane (moment about -y_p, shear and load along z_p) give the
    planar engine's M and f at random states to 1e-10, and its gravity potential."""
    planar = builtin_model("falling-beam")
    spatial = as_spatial(planar)
    beam = spatial.beams["B"]
    beam.n_modes_z, beam.shape_z, beam.n_modes_y, beam.shape_y = beam.n_modes_y, beam.shape_y, 0, beam.shape_z
    beam.principal_angle = -np.pi / 2
    spatial.validate()
    eom2, eom3 = flexkane.derive(planar, cache=False), flexkane.derive(spatial, cache=False)
    assert [q.name for q in eom3.q] == [q.name for q in eom2.q]
    system2, system3 = compact_system(eom2), compact_system(eom3)
    potential2, potential3 = (sp.lambdify([e.t, *e.q, *e.u], e.outputs["potential_gravity"].xreplace(
        e.constant_values())) for e in (eom2, eom3))
    for q, u, z, t in _random_states(planar, eom2, np.random.default_rng(8), 3):
        T, c = _free_joint_speeds(planar, eom2, q, u)
        u3 = np.linalg.solve(T, u)
        M2, f2, _ = system2(q, u, z, t)
        M3, f3, _ = system3(q, u3, z, t)
        expected_M, expected_f = T.T @ M2 @ T, T.T @ (f2 - M2 @ c)
        assert np.abs(M3 - expected_M).max() <= 1e-10 * max(1.0, np.abs(expected_M).max())
        assert np.abs(f3 - expected_f).max() <= 1e-10 * max(1.0, np.abs(expected_f).max())
        V2 = potential2(t, *q, *u)
        assert abs(potential3(t, *q, *u3) - V2) <= 1e-10 * max(1.0, abs(V2))


@pytest.mark.slow
@pytest.mark.parametrize("name", PLANAR_BUILTINS)
def test_every_planar_builtin_runs_through_the_spatial_engine_as_through_the_planar_one(name):
    """Each planar built-in model and its spatial form compiled and run for 0.02 s at tight
    tolerance: the coordinates, controller states and energies agree to 1e-9 of their range (the
    speeds of planar free joints are other speeds in 3D, compared through the coordinates)."""
    planar = builtin_model(name)
    runs = [flexkane.simulate(flexkane.compile_model(flexkane.derive(m, cache=False)), t_end=0.02, dt_out=0.002,
                              rtol=1e-12, atol=1e-13) for m in (planar, as_spatial(planar))]
    eom2 = flexkane.derive(planar)
    for column in [q.name for q in eom2.q] + [z.name for z in eom2.z]:
        a = runs[0].state[:, runs[0].state_names.index(column)]
        b = runs[1].state[:, runs[1].state_names.index(_spatial_name(planar, column))]
        assert np.abs(b - a).max() <= 1e-9 * max(1.0, np.abs(a).max()), column
    for output in ("kinetic", "potential_gravity", "strain", "energy"):
        a, b = runs[0].outputs[output], runs[1].outputs[output]
        assert np.abs(b - a).max() <= 1e-9 * max(1.0, np.abs(a).max()), output
