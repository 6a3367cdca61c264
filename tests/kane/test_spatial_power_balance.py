"""Power balance of a driven, damped spatial arm: the work of the driver, the actuators and the
dampers (integrated with the motion) equals the change of kinetic plus potential energy.

Waist about the vertical driven by a speed law, shoulder about a horizontal axis with an actuator
torque and a damper, elbow about a skew axis with a spring and a damper, a load in body axes on the
forearm, gravity.
"""

import numpy as np
import pytest
import sympy as sp

import flexkane
from flexkane.model import loads_model
from spatial_models import accelerations

ARM = """
name = "driven-damped-arm"
dimensions = 3

[bodies.base]
mass = 4.0
inertia = [0.05, 0.05, 0.03]
points = { bottom = [0, 0, -0.1], top = [0, 0, 0.1] }

[bodies.upper]
mass = 2.0
inertia = [[0.06, 0.001, 0.0], [0.001, 0.06, 0.002], [0.0, 0.002, 0.004]]
points = { a = [0, 0, -0.25], b = [0.01, 0, 0.25] }

[bodies.fore]
mass = 1.0
inertia = [0.02, 0.02, 0.002]
points = { a = [0, 0, -0.2], tool = [0, 0, 0.2] }

[joints.waist]
type = "revolute"
parent = "ground"
child = "base"
parent_position = [0, 0, 0.1]
child_point = "bottom"
axis = [0, 0, 1]
driver = { speed = "1.5*sin(2*t)" }

[joints.shoulder]
type = "revolute"
parent = "base"
child = "upper"
parent_point = "top"
child_point = "a"
axis = [0, 1, 0]
orientation = { axis = [0, 0, 1], angle = 0.2 }
torque = "3*cos(t)"
damping = 0.4

[joints.elbow]
type = "revolute"
parent = "upper"
child = "fore"
parent_point = "b"
child_point = "a"
axis = [0, 1, 1]
stiffness = 5.0
rest = 0.3
damping = 0.2

[loads.tool]
body = "fore"
point = "tool"
force = [0.5, "sin(3*t)", 0]
torque = [0, 0, 0.1]
frame = "local"

[springs.tether]
body_a = "ground"
position_a = [0.3, 0.2, 0.0]
body_b = "fore"
point_b = "tool"
stiffness = 30.0
damping = 0.5
rest_length = 0.4

[gravity]
g = 9.81
direction = [0, 0, -1]

[initial]
q_shoulder = 0.5
q_elbow = -0.4
u_elbow = 1.0
"""


def test_power_of_nonconservative_forces_is_the_rate_of_energy_at_random_states():
    eom = flexkane.derive(loads_model(ARM), cache=False)
    values = eom.constant_values()
    E, P = eom.outputs["energy"], eom.outputs["power_nonconservative"]
    rate = (sum(sp.diff(E, q) * qd for q, qd in zip(eom.q, eom.qdot)) + sum(sp.diff(E, u) * ud for u, ud in
            zip(eom.u, eom.ud)) + sp.diff(E, eom.t))
    args = [eom.t, *eom.q, *eom.u, *eom.ud]
    constants = {c: sp.Float(values[c]) for c in eom.constants}
    balance = sp.lambdify(args, [rate.xreplace(constants), P.xreplace(constants)])
    ud = accelerations(eom)
    rng = np.random.default_rng(5)
    for _ in range(4):
        q, u, t = rng.uniform(-1, 1, len(eom.q)), rng.uniform(-2, 2, len(eom.u)), rng.uniform(0, 3)
        dE, power = balance(t, *q, *u, *ud(q, u, t))
        assert abs(power) > 0.1
        assert abs(dE - power) <= 1e-10 * max(1.0, abs(power))


@pytest.mark.slow
def test_driven_damped_spatial_arm_power_balance():
    model = loads_model(ARM)
    compiled = flexkane.compile_model(flexkane.derive(model, cache=False))
    res = flexkane.simulate(compiled, t_end=3.0, dt_out=0.01, rtol=1e-11, atol=1e-12)
    energy, work = res.outputs["energy"], res.outputs["work"]
    assert np.abs(work).max() > 1.0                      # the driver, torque and dampers do work
    assert np.abs(res.outputs["energy_balance"]).max() <= 1e-8 * np.abs(energy).max()
    assert "effort_waist" in res.outputs
