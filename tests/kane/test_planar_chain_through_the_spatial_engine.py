"""A planar chain derived by the spatial engine (``as_spatial``: z normal, motion in the x-y plane)
gives the planar engine's accelerations to 1e-10.

The chain has a free joint (the spatial ``planar`` joint), a revolute joint with a spring, a damper,
an actuator torque and a constant angle, a prismatic joint along a turned axis with a spring, a weld,
gravity, a load with a force in local axes and a torque, and a spring between a ground point and a
body point. The planar free joint's speeds are velocity components along the child's axes (eq.
8.10), the spatial planar joint's the rates of x and y: the test maps one to the other.
"""

import numpy as np
import pytest

import flexkane
from flexkane.model import loads_model
from flexkane.model.as_spatial import as_spatial
from spatial_models import accelerations

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
