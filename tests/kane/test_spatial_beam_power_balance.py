"""Power balance of a driven, damped spatial chain with beams: the power of the driver, the
actuator, the joint damper, a load and the beams' modal damping equals the rate of the kinetic
(sections' turns included), strain and gravity energy, at random states along the equations of
motion (the rate taken symbolically, the accelerations from the equations).

A waist about the vertical driven by a speed law carries a flexible arm on a shoulder with an
actuator torque and a damper; the arm bends in both planes, twists and stretches (geometric
stiffening, Rayleigh sections, modal damping of every kind) and carries a payload at its tip,
loaded by a force in its own axes; gravity.
"""

import numpy as np
import pytest
import sympy as sp

import flexkane
from flexkane.model import loads_model
from spatial_models import accelerations

ARM = """
name = "driven-damped-flexible-arm"
dimensions = 3

[bodies.base]
mass = 4.0
inertia = [0.05, 0.05, 0.03]
points = { top = [0, 0, 0.1] }

[beams.arm]
L = 0.8
rho = 1.2
EI_y = 40.0
EI_z = 60.0
GJ = 15.0
rho_Ip = 0.002
rho_Iy = 0.001
rho_Iz = 0.0015
EA = 5000.0
n_modes_y = 1
n_modes_z = 1
n_torsion = 1
n_axial = 1
principal_angle = 0.2
geometric_stiffening = true
damping_y = 0.02
damping_z = 0.03
torsion_damping = 0.05
axial_damping = 0.01

[bodies.payload]
mass = 0.5
inertia = [[0.002, 0.0001, 0.0], [0.0001, 0.003, 0.0], [0.0, 0.0, 0.0025]]
points = { grip = [-0.05, 0.0, 0.01] }

[joints.waist]
type = "revolute"
parent = "ground"
child = "base"
axis = [0, 0, 1]
driver = { speed = "1.5*sin(2*t)" }

[joints.shoulder]
type = "revolute"
parent = "base"
child = "arm"
parent_point = "top"
axis = [0, 1, 0]
orientation = { axis = [0, 0, 1], angle = 0.2 }
torque = "3*cos(t)"
damping = 0.4

[joints.tip]
type = "weld"
parent = "arm"
station = 0.8
child = "payload"
child_point = "grip"

[loads.push]
body = "payload"
force = [0.5, "sin(3*t)", 0.2]
frame = "local"

[gravity]
g = 9.81
direction = [0, 0, -1]
"""


SMALL = """
name = "driven-damped-blade"
dimensions = 3

[beams.blade]
L = 0.8
rho = 1.2
EI_y = 40.0
EI_z = 60.0
GJ = 15.0
rho_Ip = 0.002
rho_Iy = 0.001
rho_Iz = 0.0015
n_modes_y = 1
n_modes_z = 1
n_torsion = 1
principal_angle = 0.2
geometric_stiffening = true
damping_y = 0.02
damping_z = 0.03
torsion_damping = 0.05

[joints.hub]
type = "revolute"
parent = "ground"
child = "blade"
axis = [0, 1, 1]
torque = "3*cos(t)"
damping = 0.3

[loads.push]
body = "blade"
station = 0.8
force = [0.5, "sin(3*t)", 0.2]
torque = [0.1, 0, 0]
frame = "local"

[gravity]
g = 9.81
direction = [0, 0, -1]
"""


def _check_power_balance(text, seed):
    """At random states: the rate of the energy along the equations of motion equals the power of
    the non-conservative forces, of which the beams' modal damping dissipates a part."""
    eom = flexkane.derive(loads_model(text), cache=False)
    values = eom.constant_values()
    constants = {c: sp.Float(values[c]) for c in eom.constants}
    E, P = eom.outputs["energy"], eom.outputs["power_nonconservative"]
    rate = (sum(sp.diff(E, q) * qd for q, qd in zip(eom.q, eom.qdot)) + sum(sp.diff(E, u) * ud for u, ud in
            zip(eom.u, eom.ud)) + sp.diff(E, eom.t))
    balance = sp.lambdify([eom.t, *eom.q, *eom.u, *eom.ud], [rate.xreplace(constants), P.xreplace(constants)])
    modal = sum(u * f for u, f in zip(eom.chain.u, eom.F_r["damping"]))       # the speeds, driven ones too
    assert modal != 0
    damping = sp.lambdify([*eom.chain.u], modal.xreplace(constants))
    ud = accelerations(eom)
    rng = np.random.default_rng(seed)
    for _ in range(3):
        q, u, t = rng.uniform(-0.3, 0.3, len(eom.q)), rng.uniform(-2, 2, len(eom.u)), rng.uniform(0, 3)
        dE, power = balance(t, *q, *u, *ud(q, u, t))
        own = [u[eom.u.index(v)] if v in eom.u else 0.0 for v in eom.chain.u]
        assert abs(power) > 0.1 and damping(*own) < -1e-3 * abs(power)     # the modal damping dissipates
        assert abs(dE - power) <= 1e-10 * max(1.0, abs(power))


def test_power_balance_of_an_actuated_damped_rayleigh_blade():
    """A blade on a hub with an actuator torque and a damper, every kind of beam term and a tip
    load, at t = 0 (its energy has no explicit time, so its rate is that along q' and u', by
    central differences): the rate of the energy is the power; the arm below, with a driver, is
    the larger case."""
    from test_spatial_beams import _compact_functions, _rates

    eom = flexkane.derive(loads_model(SMALL), cache=False)
    modal = sum(u * f for u, f in zip(eom.chain.u, eom.F_r["damping"]))
    rng = np.random.default_rng(3)
    states = [(rng.uniform(-0.3, 0.3, len(eom.q)), rng.uniform(-2, 2, len(eom.u))) for _ in range(3)]
    rates = _rates(eom, ("energy",), states)[:, 0]
    outputs = eom.compact.outputs
    power = _compact_functions(eom, [outputs["power_nonconservative"], modal])
    for (q, u), rate in zip(states, rates):
        total, dissipated = power(q, u)
        assert abs(total) > 0.1 and dissipated < -1e-3 * abs(total)       # the modal damping dissipates
        assert abs(rate - total) <= 1e-9 * max(1.0, abs(total)), (rate, total)


@pytest.mark.slow
def test_power_balance_of_a_driven_damped_flexible_arm():
    _check_power_balance(ARM, 3)
