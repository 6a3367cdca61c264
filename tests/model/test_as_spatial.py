"""A planar model as the equivalent spatial model: every part rewritten for dimensions = 3."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

from flexkane.builtin import builtin_model, builtin_names
from flexkane.errors import ModelError, ModelErrors
from flexkane.model import Orientation, as_spatial, dumps_model, loads_model
from flexkane.model.coordinates import coordinate_names
from flexkane.model.field_values import FieldValues
from flexkane.model.initial import initial_values
from flexkane.model.orientation import orientation_matrix

RIGID = """
name = "rigid-planar"
[parameters]
a = 0.2
m = 1.5
[bodies.b]
mass = "m"
inertia = 0.1
points = { P = [0.5, 0], Q = [-0.5, 0.1] }
outline = [[0.5, 0], [-0.5, 0]]
[bodies.c]
mass = 1
inertia = "a"
[bodies.d]
mass = 1
inertia = 0
[bodies.e]
mass = 2
inertia = 0.3
[joints.j]
type = "free"
parent = "ground"
child = "b"
parent_position = [1, 2]
angle = 0.3
[joints.k]
type = "prismatic"
parent = "b"
parent_point = "P"
child = "c"
axis = "a"
angle = "a"
stiffness = 10
[joints.r]
type = "revolute"
parent = "b"
parent_point = "Q"
child = "d"
angle = 0.1
torque = "sin(t)"
[joints.w]
type = "weld"
parent = "d"
child = "e"
[gravity]
g = 9.81
direction = [0, -1]
[loads.f]
body = "c"
force = [1, 2]
torque = "sin(t)"
[springs.s]
body_a = "ground"
position_a = [0, 1]
body_b = "e"
stiffness = 3
[initial]
u_j_x = 1
u_j_y = 2
q_j_angle = 0.1
q_r = 0.4
"""


def test_a_rigid_planar_model_becomes_a_valid_spatial_one():
    planar = loads_model(RIGID)
    spatial = as_spatial(planar)
    assert planar.dimensions == 2 and spatial.dimensions == 3
    assert loads_model(dumps_model(spatial)) == spatial
    assert spatial.bodies["b"].inertia == (0.1, 0.1, 0.1) and spatial.bodies["c"].inertia == ("a", "a", "a")
    assert spatial.bodies["b"].points == {"P": (0.5, 0, 0), "Q": (-0.5, 0.1, 0)}
    assert spatial.bodies["b"].outline == [(0.5, 0, 0), (-0.5, 0, 0)]
    j, k, r, w = (spatial.joints[n] for n in "jkrw")
    assert (j.type, j.axis, j.parent_position) == ("planar", (0, 0, 1), (1, 2, 0))
    assert j.child_orientation == Orientation(axis=(0, 0, 1), angle=-0.3)
    assert k.axis == ("cos(a)", "sin(a)", 0) and k.child_orientation.angle == "-(a)" and k.stiffness == 10
    assert r.axis == (0, 0, 1) and r.torque == "sin(t)" and all(x.angle == 0 for x in (j, k, r, w))
    assert w.child_orientation is None and w.axis == 0
    assert spatial.gravity.direction == (0, -1, 0)
    assert spatial.loads["f"].force == (1, 2, 0) and spatial.loads["f"].torque == (0, 0, "sin(t)")
    assert spatial.springs["s"].position_a == (0, 1, 0)
    # the planar model is not changed
    assert planar.joints["j"].type == "free" and planar.bodies["b"].inertia == 0.1


def test_coordinates_keep_their_names_and_order():
    planar = loads_model(RIGID)
    before = [(c.q, c.u, c.role) for c in coordinate_names(planar)]
    after = [(c.q, c.u, c.role) for c in coordinate_names(as_spatial(planar))]
    assert after == before


def test_the_child_frame_is_turned_by_the_planar_angle_about_z():
    """The child frame relative to J_c is the inverse of child_orientation: a turn by +angle."""
    spatial = as_spatial(loads_model(RIGID))
    fields = FieldValues(spatial)
    Oc = orientation_matrix(spatial.joints["k"].child_orientation, "joints.k.child_orientation", fields)
    c, s = math.cos(0.2), math.sin(0.2)
    assert np.allclose(Oc.T, [[c, -s, 0], [s, c, 0], [0, 0, 1]], rtol=0, atol=1e-15)


def test_free_joint_speeds_along_the_child_axes_become_rates_of_x_and_y():
    """Planar free joint: q_x' = u_x cos(phi) - u_y sin(phi), phi = q_angle + angle (eq. 8.10)."""
    values = initial_values(as_spatial(loads_model(RIGID))).values
    phi = 0.1 + 0.3
    assert values["u_j_x"] == pytest.approx(1 * math.cos(phi) - 2 * math.sin(phi), rel=1e-15)
    assert values["u_j_y"] == pytest.approx(1 * math.sin(phi) + 2 * math.cos(phi), rel=1e-15)
    assert values["q_j_angle"] == 0.1 and values["q_r"] == 0.4


@pytest.mark.parametrize("name", [n for n in builtin_names() if builtin_model(n).dimensions == 2])
def test_every_planar_builtin_converts_to_a_valid_spatial_model(name):
    """Every built-in model converts and its spatial form validates: loop constraints, distributed
    loads, the notebook variant's beam options (midpoint gravity, shear-moment elastic forces: kept,
    spatial beams have them), modal damping and rotary inertia (as damping_y and rho_Iz), drivers and
    efforts that read the state (modal names renamed); the planar model is not changed."""
    planar = builtin_model(name)
    spatial = as_spatial(planar)      # validated
    assert loads_model(dumps_model(planar)) == planar
    assert loads_model(dumps_model(spatial)) == spatial
    for beam in planar.beams.values():
        converted = spatial.beams[beam.name]
        assert (converted.gravity, converted.elastic_forces) == (beam.gravity, beam.elastic_forces)


def test_a_prismatic_loop_constraint_is_refused_by_name():
    """A planar prismatic loop joint has no spatial counterpart with its two scalar constraints: it is
    carried over and the spatial model refuses it, naming the field."""
    planar = builtin_model("four-bar")
    planar.constraints["loop"].type = "prismatic"
    spatial = as_spatial(planar, validate=False)
    with pytest.raises(ModelError) as info:
        spatial.validate()
    errors = info.value.errors if isinstance(info.value, ModelErrors) else [info.value]
    assert [e.path for e in errors] == ["constraints.loop.type"]
    assert "loop joints are planar" in str(errors[0])


def test_only_planar_models_convert():
    spatial = as_spatial(loads_model(RIGID))
    with pytest.raises(ModelError, match="dimensions: expected a planar model"):
        as_spatial(spatial)


def test_laws_that_read_planar_modal_coordinates_are_renamed():
    """A torque law reading q_<beam>_<i> and u_<beam>_<i> reads q_<beam>_y<i>, u_<beam>_y<i> in the
    spatial model (names only; q_<beam>_10 is not q_<beam>_1), and the spatial model validates."""
    planar = builtin_model("flexible-arm-lqr")
    joint = next(j for j in planar.joints.values() if isinstance(j.torque, str) and "q_link_1" in j.torque)
    spatial = as_spatial(planar)
    torque = spatial.joints[joint.name].torque
    assert torque == re.sub(r"\b([qu])_link_(\d)\b", r"\1_link_y\2", joint.torque)
    assert "q_link_y1" in torque and "u_link_y3" in torque and "k_q_link_1*" in torque   # parameters kept
    assert not re.search(r"\bq_link_1\b", torque)


def test_rename_names_changes_names_only():
    from flexkane.expression_syntax import rename_names

    names = {"q_b_1": "q_b_y1", "u_b_1": "u_b_y1", "sin": "cos"}
    assert rename_names(" -k*q_b_1 + sin(q_b_1)*u_b_1 - q_b_10 + 1e-3", names) == \
        " -k*q_b_y1 + sin(q_b_y1)*u_b_y1 - q_b_10 + 1e-3"
    assert rename_names("where(q_b_1 > 0, q_b_1, 0)", names) == "where(q_b_y1 > 0, q_b_y1, 0)"
    assert rename_names(2.5, names) == 2.5 and rename_names("q_b_1 +", names) == "q_b_1 +"


def test_loop_constraints_and_distributed_loads_convert():
    """A planar revolute loop joint becomes point_on_line along z; a distributed load keeps fx, fy."""
    four_bar = as_spatial(builtin_model("four-bar"))
    loop = four_bar.constraints["loop"]
    assert (loop.type, loop.axis, loop.dependent) == ("point_on_line", (0, 0, 1), ["u_coupler", "u_rocker"])
    mast = as_spatial(builtin_model("wind-mast"), validate=False)
    planar = builtin_model("wind-mast")
    for name, load in planar.distributed_loads.items():
        converted = mast.distributed_loads[name]
        assert (converted.fx, converted.fy, converted.fz, converted.frame) == (load.fx, load.fy, 0, load.frame)
