"""Spatial model files (dimensions = 3): reading, writing, coordinate names; planar files unchanged."""

from __future__ import annotations

import pathlib

import pytest

from flexkane.builtin import builtin_model, builtin_names
from flexkane.model import Model, Orientation, dumps_model, load_model, loads_model
from flexkane.model.coordinates import coordinate_names

HERE = pathlib.Path(__file__).parent
SPATIAL = sorted((HERE / "spatial_models").glob("*.toml"))


@pytest.mark.parametrize("path", SPATIAL, ids=lambda p: p.stem)
def test_spatial_model_file_round_trip(path):
    model = load_model(path)
    assert model.dimensions == 3
    text = dumps_model(model)
    again = loads_model(text)
    assert again == model
    assert dumps_model(again) == text


@pytest.mark.parametrize("name", [n for n in builtin_names() if builtin_model(n).dimensions == 2])
def test_planar_builtin_dumps_as_before(name):
    """The file written for every planar built-in model is byte for byte what the planar-only code
    wrote (stored in planar_dumps/), and reads back to an equal model."""
    model = builtin_model(name)
    assert model.dimensions == 2
    text = dumps_model(model)
    assert text == (HERE / "planar_dumps" / f"{name}.toml").read_text()
    assert "dimensions" not in text
    assert loads_model(text) == model


def test_spatial_fields_are_read_as_tuples_and_orientations():
    model = load_model(HERE / "spatial_models" / "two-body-arm.toml")
    assert model.bodies["bob"].inertia == (0.01, 0.01, 0.02)
    assert model.bodies["bob"].inertia_tensor() == ((0.01, 0, 0), (0, 0.01, 0), (0, 0, 0.02))
    assert model.bodies["arm2"].inertia_tensor()[0] == (0.1, 0.01, 0)
    assert model.bodies["bob"].points["top"] == (0, 0, "L")
    pivot, elbow = model.joints["pivot"], model.joints["elbow"]
    assert pivot.parent_position == (0, 0, 1)
    assert pivot.orientation == Orientation(sequence="zyx", angles=[0.1, 0.2, 0.3])
    assert elbow.axes == [(1, 0, 0), (0, 1, 0)]
    assert elbow.child_orientation == Orientation(axis=(0, 0, 1), angle="0.5")
    assert model.gravity.direction == (0, 0, -1)
    assert model.loads["push"].torque == (0, 0, 1)


def _joint_model(joint_type: str, **fields) -> Model:
    text = "\n".join([
        "dimensions = 3",
        "[bodies.b]", "mass = 1", "inertia = [1, 1, 1]",
        "[joints.j]", f'type = "{joint_type}"', 'parent = "ground"', 'child = "b"',
        *(f"{key} = {value}" for key, value in fields.items())])
    return loads_model(text)


@pytest.mark.parametrize("joint_type, fields, names", [
    ("revolute", {"axis": "[0, 0, 1]"}, [("q_j", "u_j")]),
    ("prismatic", {"axis": "[1, 0, 0]"}, [("q_j", "u_j")]),
    ("cylindrical", {"axis": "[0, 1, 0]"}, [("q_j_angle", "u_j_angle"), ("q_j_slide", "u_j_slide")]),
    ("universal", {"axes": "[[1, 0, 0], [0, 1, 0]]"}, [("q_j_1", "u_j_1"), ("q_j_2", "u_j_2")]),
    ("planar", {"axis": "[0, 0, 1]"}, [("q_j_x", "u_j_x"), ("q_j_y", "u_j_y"), ("q_j_angle", "u_j_angle")]),
    ("spherical", {}, [("q_j_e0", None), ("q_j_e1", "u_j_wx"), ("q_j_e2", "u_j_wy"), ("q_j_e3", "u_j_wz")]),
    ("free", {}, [("q_j_x", "u_j_vx"), ("q_j_y", "u_j_vy"), ("q_j_z", "u_j_vz"), ("q_j_e0", None),
                  ("q_j_e1", "u_j_wx"), ("q_j_e2", "u_j_wy"), ("q_j_e3", "u_j_wz")]),
    ("weld", {}, []),
])
def test_coordinate_names_of_each_spatial_joint(joint_type, fields, names):
    model = _joint_model(joint_type, **fields)
    coordinates = coordinate_names(model)
    assert [(c.q, c.u) for c in coordinates] == names
    assert all(c.owner == "j" for c in coordinates)


def test_sequential_naming_numbers_coordinates_and_speeds_separately():
    text = "\n".join(["dimensions = 3", 'naming = "sequential"', "[bodies.b]", "mass = 1", "inertia = [1, 1, 1]",
                      "[bodies.c]", "mass = 1", "inertia = [1, 1, 1]",
                      "[joints.j]", 'type = "free"', 'parent = "ground"', 'child = "b"',
                      "[joints.k]", 'type = "revolute"', 'parent = "b"', 'child = "c"', "axis = [0, 0, 1]"])
    model = loads_model(text)
    pairs = [(c.q, c.u) for c in coordinate_names(model)]
    assert pairs == [("q1", "u1"), ("q2", "u2"), ("q3", "u3"), ("q4", None), ("q5", "u4"), ("q6", "u5"),
                     ("q7", "u6"), ("q8", "u7")]


def test_custom_names_of_a_spherical_joint():
    model = _joint_model("spherical", coordinates='["a0", "a1", "a2", "a3"]', speeds='["w1", "w2", "w3"]')
    assert [(c.q, c.u) for c in coordinate_names(model)] == [("a0", None), ("a1", "w1"), ("a2", "w2"),
                                                             ("a3", "w3")]


def test_the_readme_example_of_a_spatial_model_is_valid(capsys):
    from flexkane.cli import main

    readme = (HERE.parents[1] / "README.md").read_text()
    section = readme[readme.index("### Spatial models (`dimensions = 3`)"):]
    text = section[section.index("```toml") + len("```toml"):section.index("```\n", section.index("```toml") + 7)]
    model = loads_model(text)
    assert model.dimensions == 3
    names = [(c.q, c.u) for c in coordinate_names(model)]
    assert names[:2] == [("q_shoulder_1", "u_shoulder_1"), ("q_shoulder_2", "u_shoulder_2")]
    assert names[2] == ("q_elbow_e0", None)
    path = HERE / "spatial_models" / "two-body-arm.toml"
    assert main(["check", str(path)]) == 0
    out = capsys.readouterr().out
    assert "valid (spatial, 2 bodies" in out and "6 generalized coordinates" in out and "5 generalized speeds" in out


def test_reading_and_checking_a_planar_model_imports_no_numpy():
    """The spatial checks (NumPy) load only for spatial models: planar `flexkane check` starts as fast
    as before."""
    import subprocess
    import sys

    code = ("import sys\nfrom flexkane.builtin import builtin_model\nfrom flexkane.model.coordinates import "
            "coordinate_names\nm = builtin_model('four-bar').validate()\ncoordinate_names(m)\n"
            "print('numpy' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "False"
