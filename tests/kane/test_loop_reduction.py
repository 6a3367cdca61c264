"""The reduction of Kane's equations by closed loops is a value: a pure function of the equations
over the free speeds, whose result the equations take once (kane.loop_reduction)."""

from __future__ import annotations

import dataclasses

import pytest
import sympy as sp

import flexkane
from flexkane.kane.loop_reduction import LoopReduction, reduce_by_loops
from reduction_recording import derive_recording


#: A slider-crank with a crank driven by a law of time and a rod of one bending mode (small, fast).
SLIDER_CRANK = """
name = "small-slider-crank"
[parameters]
m1 = 0.36
L1 = 0.15
J1 = 0.0007
L2 = 0.30
EI = 70.0
rho = 0.5
m3 = 0.075
Omega = 150.0
[bodies.crank]
mass = "m1"
inertia = "J1"
points = { pivot = ["-L1/2", 0], pin = ["L1/2", 0] }
[beams.rod]
L = "L2"
EI = "EI"
rho = "rho"
n_modes = 1
shape = { family = "expression", expressions = ["sin(pi*xi)"], boundary = "pinned-pinned" }
[bodies.slider]
mass = "m3"
inertia = 0
[joints.crank]
type = "revolute"
parent = "ground"
child = "crank"
child_point = "pivot"
driver = { coordinate = "Omega*t" }
[joints.rod]
type = "revolute"
parent = "crank"
parent_point = "pin"
child = "rod"
[joints.slider]
type = "prismatic"
parent = "ground"
child = "slider"
[constraints.piston]
type = "revolute"
body_a = "rod"
station_a = "L2"
body_b = "slider"
[initial]
q_slider = 0.45
"""


@pytest.fixture(scope="module")
def slider_crank():
    """The slider-crank's equations and the one call of the loop reduction made while deriving them."""
    eom, calls = derive_recording(flexkane.loads_model(SLIDER_CRANK), "reduce_by_loops", reduce_by_loops)
    assert len(calls) == 1
    return eom, calls[0]


def test_every_attribute_of_equations_with_a_closed_loop_is_set_once(slider_crank):
    eom, _ = slider_crank
    twice = {name: n for name, n in eom.writes.items() if n > 1}
    assert twice == {}
    for name in ("mass_matrix", "forcing", "qdot", "zdot", "outputs", "u", "ud", "driver_efforts",
                 "dependent_speeds", "dependent_coordinates", "_phi", "constraint_set"):
        assert eom.writes[name] == 1, name


def test_the_loop_reduction_leaves_its_inputs_unchanged_and_gives_the_same_value_twice(slider_crank):
    eom, (args, kwargs, before, result) = slider_crank
    for given, copy in zip(args, before):
        if copy is not None:
            assert given == copy
    again = reduce_by_loops(*args, **kwargs)
    assert again == result
    assert isinstance(result, LoopReduction)
    with pytest.raises(dataclasses.FrozenInstanceError):
        result.u = ()


def test_the_equations_are_the_loop_reduction_s_result(slider_crank):
    eom, (args, _, before, result) = slider_crank
    # the crank's speed is prescribed, the two constraints make the rod's and the slider's dependent:
    # the rod's modal speed is the one independent speed
    assert [u.name for u in result.dependent_speeds] == ["u_slider", "u_rod"]
    assert list(eom.dependent_speeds) == list(result.dependent_speeds)
    assert [u.name for u in before[6]] == ["u_slider", "u_rod", "u_rod_1"] and eom.u == list(result.u)
    assert [u.name for u in eom.u] == ["u_rod_1"]
    assert eom.dependent_coordinates == list(result.dependent_coordinates)
    assert eom.compact.mass_matrix == result.mass_matrix and eom.compact.forcing == result.forcing
    assert eom.driver_efforts == result.driver_efforts and list(eom.driver_efforts) == ["crank"]
    assert eom._phi == list(result.phi) and eom.constraint_set is result.constraint_set
    # the driver's effort is corrected by the constraint forces: it reads the accelerations of the
    # independent speeds only
    dependent = set(result.dependent_speeds) | {eom.chain.ud[u] for u in result.dependent_speeds}
    assert result.driver_efforts["crank"] != before[8]["crank"]
    assert eom.expand(before[8]["crank"]).free_symbols & dependent
    assert not eom.expand(result.driver_efforts["crank"]).free_symbols & dependent


def test_the_reduced_mass_matrix_is_the_kinetic_energy_s_in_the_independent_speed(slider_crank):
    """P^T M P = d^2 T / du_i^2, T the kinetic energy with the dependent speeds written in the
    independent one (and the crank's law): an identity in q and t, checked at a configuration."""
    eom, (_, _, _, result) = slider_crank
    [u] = eom.u
    values = {k: sp.Float(v) for k, v in eom.constant_values().items()}
    at = {**{q: sp.Float(x) for q, x in zip(eom.q, (0.4, -0.3, 0.002))}, eom.t: sp.Float(0.001)}
    mass = float(eom.expand(result.mass_matrix[0, 0]).xreplace(values).xreplace(at))
    kinetic = float(sp.diff(eom.expand(eom.compact.outputs["kinetic"]), u, 2).xreplace(values).xreplace(at))
    assert mass == pytest.approx(kinetic, rel=1e-12)
