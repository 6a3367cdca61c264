"""A planar model derived by the spatial engine (planar motion: turns about z, translations in the
plane) has the planar engine's equations: the same coordinates, speeds, constants and outputs by
name, and the same mass matrix, forcing and outputs at any state (to round-off).

The chains use every part the planar engine has that the spatial engine now derives for planar
models: free (speeds along the child's axes, eq. 8.10), revolute, prismatic (turned axis) and weld
joints with constant angles, joint springs, dampers and actuator torques, gravity, loads with forces
in ground and local axes and torques, springs between points; beams with several modes, axial modes
and geometric stiffening, rotary inertia (Rayleigh sections), modal damping, a distributed load, a
body and a spring at stations, and a sensor feeding a joint torque.
"""

import numpy as np
import pytest
import sympy as sp

from flexkane.errors import ModelError
from flexkane.kane import derive
from flexkane.model import loads_model
from test_planar_chain_through_the_spatial_engine import PLANAR

#: The chain of the test through ``as_spatial``, with a second load in ground axes.
RIGID = PLANAR + """
[loads.wind]
body = "carrier"
force = [0.4, 0.1]
"""

FLEXIBLE = """
name = "planar-flexible"

[parameters]
L = 1.2

[bodies.hub]
mass = 2.0
inertia = 0.05
points = { clamp = [0.05, 0.0] }

[beams.link]
L = "L"
EI = 12.0
rho = 0.6
EA = 4000.0
n_modes = 2
n_axial = 1
rotary_inertia = 1e-3
geometric_stiffening = true
damping = [0.02, 0.03]

[bodies.payload]
mass = 0.25
inertia = 5e-4
points = { a = [-0.02, 0.0] }

[joints.shoulder]
type = "revolute"
parent = "ground"
child = "hub"
torque = "-0.8*tip - 0.1*hub_speed"

[joints.clamp]
type = "weld"
parent = "hub"
parent_point = "clamp"
child = "link"
angle = 0.1

[joints.wrist]
type = "revolute"
parent = "link"
station = "L"
child = "payload"
child_point = "a"
stiffness = 3.0

[sensors.tip]
type = "tip_deflection"
beam = "link"

[sensors.hub_speed]
type = "velocity"
body = "link"
station = "L/2"
component = "y"
frame = "local"

[gravity]
g = 9.81
direction = [0, -1]

[loads.poke]
body = "link"
station = "L/2"
force = [0.0, 0.3]
frame = "ground"

[distributed_loads.breeze]
beam = "link"
frame = "ground"
fx = "0.5*(x/L)"
fy = "0.2*sin(t)"

[springs.guy]
body_a = "ground"
position_a = [0.3, -0.6]
body_b = "link"
station_b = "L/2"
rest_length = 0.4
stiffness = 50.0
"""


def _both(text):
    model = loads_model(text)
    return derive(model, engine="planar"), derive(model, engine="spatial")


def _values(eom, rng):
    state = {s: v for s, v in zip(eom.q, rng.uniform(-0.6, 0.6, len(eom.q)))}
    state.update({s: v for s, v in zip(eom.u, rng.uniform(-1.5, 1.5, len(eom.u)))})
    state[eom.t] = rng.uniform(0.0, 2.0)
    return {**eom.constant_values(), **state}


def _number(expr, at):
    return float(sp.sympify(expr).xreplace(at))


@pytest.mark.parametrize("text", [RIGID, FLEXIBLE], ids=["rigid", "flexible"])
def test_spatial_engine_gives_the_planar_engines_names(text):
    planar, spatial = _both(text)
    assert [s.name for s in spatial.q] == [s.name for s in planar.q]
    assert [s.name for s in spatial.u] == [s.name for s in planar.u]
    assert sorted(s.name for s in spatial.constants) == sorted(s.name for s in planar.constants)
    assert spatial.output_names == planar.output_names


@pytest.mark.parametrize("text", [RIGID, FLEXIBLE], ids=["rigid", "flexible"])
def test_spatial_engine_gives_the_planar_engines_equations_and_outputs(text):
    planar, spatial = _both(text)
    rng = np.random.default_rng(11)
    for _ in range(3):
        at = _values(planar, rng)
        for attribute in ("mass_matrix", "forcing"):
            a = np.array([_number(e, at) for e in getattr(planar, attribute)])
            b = np.array([_number(e, at) for e in getattr(spatial, attribute)])
            assert np.abs(b - a).max() <= 1e-12 * max(1.0, np.abs(a).max()), attribute
        for name, expr in planar.outputs.items():
            if name.startswith("theta_"):     # angles agree up to the turns the numbers carry
                continue
            a, b = _number(expr, at), _number(spatial.outputs[name], at)
            assert abs(b - a) <= 1e-12 * max(1.0, abs(a)), name


@pytest.mark.parametrize("n", [1, 2, 3])
def test_the_chapter_example_gets_the_planar_engines_expressions_themselves(n):
    """The falling beam of eqs. 8.23 and 8.31: the same SymPy expressions (not only equal values),
    so that it prints term by term as the planar engine printed it."""
    from flexkane.builtin import builtin_model

    model = builtin_model("falling-beam-exact").with_modes(n)
    planar, spatial = derive(model, engine="planar"), derive(model, engine="spatial")
    assert spatial.intermediates == planar.intermediates
    assert list(spatial.compact_forces["F_r_star"]) == list(planar.compact_forces["F_r_star"])
    assert spatial.compact_forces["F_r"] == planar.compact_forces["F_r"]
    assert spatial.compact.mass_matrix == planar.compact.mass_matrix
    assert spatial.compact.forcing == planar.compact.forcing


def test_an_unknown_engine_is_refused_by_name():
    with pytest.raises(ModelError, match="engine"):
        derive(loads_model(RIGID), engine="cylindrical")
