"""Every invalid field of a spatial model (dimensions = 3) is refused by ``flexkane check`` with exit
code 2 and a one-line message naming the field, what was expected and what was given; initial
orientations become Euler parameters."""

from __future__ import annotations

import copy

import numpy as np
import pytest
import tomli_w

from flexkane.cli import main
from flexkane.errors import ModelError
from flexkane.model import loads_model
from flexkane.model.initial import initial_values

BASE = {
    "name": "spatial-check",
    "dimensions": 3,
    "parameters": {"L": 0.5},
    "bodies": {
        "b": {"mass": 1.0, "inertia": [0.1, 0.2, 0.25], "points": {"P": [0, 0, "L"]},
              "outline": [[0, 0, 0], [0, 0, "L"]]},
        "c": {"mass": 1.0, "inertia": [[0.1, 0.01, 0], [0.01, 0.2, 0], [0, 0, 0.25]]},
        "d": {"mass": 1.0, "inertia": [0.1, 0.1, 0.1]},
    },
    "joints": {
        "j": {"type": "revolute", "parent": "ground", "child": "b", "axis": [0, 0, 1],
              "parent_position": [0, 0, 1], "orientation": {"sequence": "zyx", "angles": [0.1, 0.2, 0.3]}},
        "s": {"type": "spherical", "parent": "b", "child": "c", "parent_point": "P"},
        "u": {"type": "universal", "parent": "c", "child": "d", "axes": [[1, 0, 0], [0, 1, 0]],
              "child_orientation": {"axis": [0, 0, 1], "angle": 0.5}},
    },
    "gravity": {"g": 9.81, "direction": [0, 0, -1]},
    "loads": {"f": {"body": "b", "force": [1, 0, "sin(t)"], "torque": [0, 0, 1]}},
    "springs": {"k": {"body_a": "ground", "position_a": [0, 0, 2], "body_b": "d", "stiffness": 10}},
    "initial": {"q_s": {"axis": [1, 0, 0], "angle": 0.3}, "u_s_wx": 1.0},
}


def _set(data: dict, path: str, value) -> None:
    keys = path.split(".")
    for key in keys[:-1]:
        data = data.setdefault(key, {})
    if value is _DELETE:
        del data[keys[-1]]
    else:
        data[keys[-1]] = value


_DELETE = object()

#: (case id, {key path: new value}, key path named by the message, words the message says)
CASES = [
    ("dimensions-4", {"dimensions": 4}, "dimensions", ["2 (a planar chain) or 3"]),
    ("dimensions-text", {"dimensions": "3"}, "dimensions", ["2 (a planar chain) or 3"]),
    ("inertia-two-values", {"bodies.b.inertia": [1, 2]}, "bodies.b.inertia", ["three principal values", "kg m^2"]),
    ("inertia-not-symmetric", {"bodies.c.inertia": [[0.1, 0.02, 0], [0.01, 0.2, 0], [0, 0, 0.25]]},
     "bodies.c.inertia[0][1]", ["symmetric"]),
    ("inertia-negative", {"bodies.b.inertia": [-0.1, 0.2, 0.25]}, "bodies.b.inertia", ["non-negative"]),
    ("inertia-triangle", {"bodies.b.inertia": [0.1, 0.1, 0.3]}, "bodies.b.inertia", ["triangle inequality"]),
    ("inertia-tensor-indefinite", {"bodies.c.inertia": [[0.1, 0.3, 0], [0.3, 0.2, 0], [0, 0, 0.25]]},
     "bodies.c.inertia", ["non-negative principal moments"]),
    ("inertia-short-row", {"bodies.c.inertia": [[0.1, 0.01, 0], [0.01, 0.2], [0, 0, 0.25]]},
     "bodies.c.inertia[1]", ["a row of three"]),
    ("inertia-unknown-name", {"bodies.b.inertia": ["Ixx", 0.2, 0.25]}, "bodies.b.inertia[0]", ["Ixx"]),
    ("point-two-components", {"bodies.b.points": {"P": [0, 1]}}, "bodies.b.points.P", ["three values [x, y, z]"]),
    ("outline-two-components", {"bodies.b.outline": [[0, 0], [0, 1]]}, "bodies.b.outline[0]",
     ["three values [x, y, z]"]),
    ("revolute-without-axis", {"joints.j.axis": _DELETE}, "joints.j.axis", ["rotation axis", "missing"]),
    ("revolute-zero-axis", {"joints.j.axis": [0, 0, 0]}, "joints.j.axis", ["non-zero vector"]),
    ("revolute-axis-angle", {"joints.j.axis": 0.5}, "joints.j.axis", ["three values [x, y, z]"]),
    ("revolute-axis-two-components", {"joints.j.axis": [0, 1]}, "joints.j.axis", ["three values [x, y, z]"]),
    ("axis-on-spherical", {"joints.s.axis": [0, 0, 1]}, "joints.s.axis", ["no axis"]),
    ("universal-without-axes", {"joints.u.axes": _DELETE}, "joints.u.axes", ["two axes", "missing"]),
    ("universal-axes-not-perpendicular", {"joints.u.axes": [[1, 0, 0], [1, 1, 0]]}, "joints.u.axes",
     ["perpendicular", "cosine"]),
    ("universal-zero-axis", {"joints.u.axes": [[1, 0, 0], [0, 0, 0]]}, "joints.u.axes[1]", ["non-zero vector"]),
    ("universal-one-axis", {"joints.u.axes": [[1, 0, 0]]}, "joints.u.axes", ["two axes"]),
    ("axes-on-revolute", {"joints.j.axes": [[1, 0, 0], [0, 1, 0]]}, "joints.j.axes", ["not universal"]),
    ("orientation-both-forms", {"joints.j.orientation": {"axis": [0, 0, 1], "angle": 1, "sequence": "z",
                                                         "angles": [1]}},
     "joints.j.orientation", ["axis = [ax, ay, az], angle", "both forms"]),
    ("orientation-empty", {"joints.j.orientation": {}}, "joints.j.orientation", ["an empty table"]),
    ("orientation-unknown-key", {"joints.j.orientation": {"axis": [0, 0, 1], "angel": 1}},
     "joints.j.orientation.angel", ["did you mean 'angle'"]),
    ("orientation-bad-sequence", {"joints.j.orientation": {"sequence": "zyw", "angles": [1, 2, 3]}},
     "joints.j.orientation.sequence", ["letters among x, y, z"]),
    ("orientation-long-sequence", {"joints.j.orientation": {"sequence": "zyxz", "angles": [1, 2, 3, 4]}},
     "joints.j.orientation.sequence", ["1 to 3 letters"]),
    ("orientation-angle-count", {"joints.j.orientation": {"sequence": "zy", "angles": [1, 2, 3]}},
     "joints.j.orientation.angles", ["2 angle(s)"]),
    ("orientation-zero-axis", {"joints.u.child_orientation": {"axis": [0, 0, 0], "angle": 1}},
     "joints.u.child_orientation.axis", ["non-zero axis"]),
    ("orientation-missing-angle", {"joints.u.child_orientation": {"axis": [0, 0, 1]}},
     "joints.u.child_orientation.angle", ["missing"]),
    ("orientation-not-a-table", {"joints.j.orientation": 0.5}, "joints.j.orientation", ["sequence = \"zyx\""]),
    ("orientation-bad-angle", {"joints.j.orientation": {"axis": [0, 0, 1], "angle": "2*q"}},
     "joints.j.orientation.angle", ["q"]),
    ("planar-angle-in-3d", {"joints.j.angle": 0.2}, "joints.j.angle", ["no angle", "orientation"]),
    ("parent-position-two-components", {"joints.j.parent_position": [0, 1]}, "joints.j.parent_position",
     ["three values [x, y, z]", "[m]"]),
    ("gravity-two-components", {"gravity.direction": [0, -1]}, "gravity.direction", ["three values [x, y, z]"]),
    ("gravity-zero", {"gravity.direction": [0, 0, 0]}, "gravity.direction", ["non-zero direction"]),
    ("load-scalar-torque", {"loads.f.torque": 1.0}, "loads.f.torque", ["three values [x, y, z]", "N m"]),
    ("load-two-force-components", {"loads.f.force": [1, 0]}, "loads.f.force", ["three values [x, y, z]", "[N]"]),
    ("load-torque-not-finite", {"loads.f.torque": [0, 0, "1/(t)"]}, "loads.f.torque[2]", []),
    ("spring-position-two-components", {"springs.k.position_a": [0, 2]}, "springs.k.position_a",
     ["three values [x, y, z]"]),
    ("planar-beam-keys-in-3d", {"beams": {"B": {"L": 1, "EI": 1, "rho": 1, "n_modes": 1}},
                                "joints.w": {"type": "weld", "parent": "d", "child": "B"}},
     "beams.B.EI", ["a known key", "did you mean 'EI_z'"]),
    ("beam-load-station-beyond-L", {"beams": {"B": {"L": 1, "EI_y": 1, "EI_z": 1, "rho": 1, "n_modes_y": 1}},
                                    "joints.w": {"type": "weld", "parent": "d", "child": "B"},
                                    "loads.f": {"body": "B", "station": 1.5, "force": [1, 0, 0]}},
     "loads.f.station", ["a station 0 <= x <= L"]),
    ("beam-station-beyond-L", {"beams": {"B": {"L": 1, "EI_y": 1, "EI_z": 1, "rho": 1, "n_modes_y": 1}},
                               "joints.w": {"type": "weld", "parent": "d", "child": "B"},
                               "bodies.e": {"mass": 1.0, "inertia": [0.1, 0.1, 0.1]},
                               "joints.x": {"type": "weld", "parent": "B", "child": "e", "station": 2}},
     "joints.x.station", ["a station 0 <= x <= L"]),
    ("beam-without-EI_y", {"beams": {"B": {"L": 1, "EI_z": 1, "rho": 1, "n_modes_y": 1}},
                           "joints.w": {"type": "weld", "parent": "d", "child": "B"}},
     "beams.B.EI_y", ["flexural rigidity about the section's y axis [N m^2]"]),
    ("beam-torsion-without-GJ", {"beams": {"B": {"L": 1, "EI_y": 1, "EI_z": 1, "rho": 1, "n_torsion": 1}},
                                 "joints.w": {"type": "weld", "parent": "d", "child": "B"}},
     "beams.B.GJ", ["torsional rigidity [N m^2] (required with n_torsion > 0)"]),
    ("beam-torsion-family-bending", {"beams": {"B": {"L": 1, "EI_y": 1, "EI_z": 1, "rho": 1, "GJ": 1,
                                                     "n_torsion": 1, "torsion_shape": "clamped-free"}},
                                     "joints.w": {"type": "weld", "parent": "d", "child": "B"}},
     "beams.B.torsion_shape.family", ["a torsion shape-function family"]),
    ("beam-no-modes", {"beams": {"B": {"L": 1, "EI_y": 1, "EI_z": 1, "rho": 1}},
                       "joints.w": {"type": "weld", "parent": "d", "child": "B"}},
     "beams.B.n_modes_y", ["at least one shape function"]),
    ("beam-damping-in-3d", {"beams": {"B": {"L": 1, "EI_y": 1, "EI_z": 1, "rho": 1, "n_modes_z": 1,
                                            "damping": [0.01]}},
                            "joints.w": {"type": "weld", "parent": "d", "child": "B"}},
     "beams.B.damping", ["no damping on a beam with dimensions = 3", "damping_y, damping_z"]),
    ("beam-negative-rho_Ip", {"beams": {"B": {"L": 1, "EI_y": 1, "EI_z": 1, "rho": 1, "n_modes_z": 1,
                                              "rho_Ip": -1}},
                              "joints.w": {"type": "weld", "parent": "d", "child": "B"}},
     "beams.B.rho_Ip", ["polar mass moment of inertia"]),
    ("planar-constraint-type-in-3d", {"constraints": {"loop": {"type": "revolute", "body_a": "ground",
                                                                "body_b": "d"}}},
     "constraints.loop.type", ["spherical", "point_on_line", "weld", "planar"]),
    ("constraint-line-axis-expression", {"constraints": {"loop": {"type": "point_on_line", "body_a": "ground",
                                                                   "body_b": "d", "axis": [0, "1", 0]}}},
     "constraints.loop.axis", ["three numbers"]),
    ("constraint-orientation-not-weld", {"constraints": {"loop": {"type": "spherical", "body_a": "ground",
                                                                   "body_b": "d", "orientation": {
                                                                       "axis": [0, 0, 1], "angle": 0.1}}}},
     "constraints.loop.orientation", ["not a weld"]),
    ("constraint-dependent-count-3d", {"constraints": {"loop": {"type": "spherical", "body_a": "ground",
                                                                 "body_b": "d", "dependent": ["u_j"]}}},
     "constraints.loop.dependent", ["a list of 3 dependent speed names"]),
    ("torque-on-spherical", {"joints.s.torque": "sin(t)"}, "joints.s.torque", ["revolute or prismatic"]),
    ("driver-on-universal", {"joints.u.driver": {"coordinate": "t"}}, "joints.u.driver", ["revolute or prismatic"]),
    ("unknown-joint-type", {"joints.s.type": "ball"}, "joints.s.type", ["'spherical'"]),
    ("spherical-speeds-count", {"joints.s.speeds": ["a", "b", "c", "d"]}, "joints.s.speeds",
     ["3 spherical-joint speed names"]),
    ("spherical-coordinates-count", {"joints.s.coordinates": ["a", "b", "c"]}, "joints.s.coordinates",
     ["4 spherical-joint coordinate names"]),
    ("joint-key-typo", {"joints.u.axess": [[1, 0, 0], [0, 1, 0]]}, "joints.u.axess", ["did you mean 'axes'"]),
    ("initial-some-euler-parameters", {"initial": {"q_s_e0": 1.0, "q_s_e1": 0.0}}, "initial.q_s_e2",
     ["all four Euler parameters", "missing: q_s_e2, q_s_e3"]),
    ("initial-zero-euler-parameters", {"initial": {"q_s_e0": 0, "q_s_e1": 0, "q_s_e2": 0, "q_s_e3": 0}},
     "initial.q_s_e0", ["non-zero norm", "four zeros"]),
    ("initial-table-and-euler-parameter", {"initial": {"q_s": {"axis": [1, 0, 0], "angle": 0.3}, "q_s_e1": 0.1}},
     "initial.q_s_e1", ["no Euler parameter", "as a table"]),
    ("initial-bad-orientation", {"initial": {"q_s": {"axis": [1, 0], "angle": 0.3}}}, "initial.q_s.axis",
     ["three values [x, y, z]"]),
    ("initial-orientation-not-table", {"initial": {"q_s": 0.3}}, "initial.q_s", ["orientation of joint 's'"]),
    ("initial-table-for-revolute", {"initial": {"q_j": {"axis": [1, 0, 0], "angle": 0.3}}}, "initial.q_j",
     ["a number or an expression"]),
    ("initial-unknown-name", {"initial": {"q_x": 1.0}}, "initial.q_x", ["generalized coordinate or speed"]),
    ("initial-e0-speed", {"initial": {"u_s_e0": 1.0}}, "initial.u_s_e0", ["generalized coordinate or speed"]),
]


def _write(tmp_path, changes: dict) -> str:
    data = copy.deepcopy(BASE)
    for path, value in changes.items():
        _set(data, path, value)
    path = tmp_path / "model.toml"
    path.write_text(tomli_w.dumps(data))
    return str(path)


def test_the_base_model_is_valid(tmp_path, capsys):
    assert main(["check", _write(tmp_path, {})]) == 0
    assert "valid" in capsys.readouterr().out


@pytest.mark.parametrize("changes, path, says", [c[1:] for c in CASES], ids=[c[0] for c in CASES])
def test_check_refuses_with_exit_2_naming_the_field(tmp_path, capsys, changes, path, says):
    assert main(["check", _write(tmp_path, changes)]) == 2
    out, err = capsys.readouterr()
    assert out == "" and "Traceback" not in err
    assert err.startswith(f"flexkane: error: {path}: expected "), err
    for text in says:
        assert text in err, (text, err)


def test_planar_models_refuse_spatial_fields_and_types(tmp_path, capsys):
    planar = {"bodies": {"b": {"mass": 1, "inertia": 1}},
              "joints": {"j": {"type": "spherical", "parent": "ground", "child": "b"}}}
    path = tmp_path / "planar.toml"
    path.write_text(tomli_w.dumps(planar))
    assert main(["check", str(path)]) == 2
    err = capsys.readouterr().err
    assert "joints.j.type: expected one of 'free'" in err and "dimensions = 3" in err
    planar["joints"]["j"] = {"type": "revolute", "parent": "ground", "child": "b",
                             "orientation": {"axis": [0, 0, 1], "angle": 1}}
    path.write_text(tomli_w.dumps(planar))
    assert main(["check", str(path)]) == 2
    assert "joints.j.orientation: expected no orientation in a planar model" in capsys.readouterr().err


def _spatial(initial: dict):
    data = copy.deepcopy(BASE)
    data["initial"] = initial
    return loads_model(tomli_w.dumps(data))


def test_initial_orientation_tables_become_euler_parameters():
    values = initial_values(_spatial({"q_s": {"axis": [0, 0, 2], "angle": 1.0}})).values
    e = [values[f"q_s_e{k}"] for k in range(4)]
    assert np.allclose(e, [np.cos(0.5), 0, 0, np.sin(0.5)], rtol=0, atol=1e-15)
    values = initial_values(_spatial({"q_s": {"sequence": "z", "angles": [1.0]}})).values
    assert np.allclose([values[f"q_s_e{k}"] for k in range(4)], e, rtol=0, atol=1e-15)
    identity = initial_values(_spatial({})).values
    assert [identity[f"q_s_e{k}"] for k in range(4)] == [1.0, 0.0, 0.0, 0.0]
    assert list(identity)[:6] == ["q_j", "q_s_e0", "q_s_e1", "q_s_e2", "q_s_e3", "q_u_1"]


def test_given_euler_parameters_are_normalized_with_a_warning_when_off():
    found = initial_values(_spatial({"q_s_e0": 2.0, "q_s_e1": 0, "q_s_e2": 0, "q_s_e3": 0}))
    assert [found.values[f"q_s_e{k}"] for k in range(4)] == [1.0, 0.0, 0.0, 0.0]
    assert len(found.warnings) == 1 and "norm 2" in found.warnings[0]
    near = initial_values(_spatial({"q_s_e0": 1 + 1e-12, "q_s_e1": 0, "q_s_e2": 0, "q_s_e3": 0}))
    assert near.warnings == []
    assert near.values["q_s_e0"] == 1.0


def test_python_built_models_get_the_same_checks():
    model = _spatial({})
    model.joints["u"].axes = [(1, 0, 0), (1, 0, 0)]
    with pytest.raises(ModelError, match=r"joints\.u\.axes: expected two perpendicular axes"):
        model.validate()


def test_mutated_spatial_models_give_a_model_error_or_a_valid_model():
    """Extreme numbers, wrong types, hostile expressions, deleted and misspelled keys in spatial model
    files (the mutations of the planar fuzz tests): a ModelError or a valid model, never another
    exception nor a numeric warning (huge components are scaled before norms and eigenvalues)."""
    import pathlib
    import random
    import sys
    import tomllib
    import warnings

    sys.path.insert(0, str(pathlib.Path(__file__).parents[1] / "validation"))
    import model_mutations

    bases = [tomli_w.dumps(BASE), (pathlib.Path(__file__).parent / "spatial_models" / "two-body-arm.toml").read_text()]
    outcomes = {"valid": 0, "refused": 0}
    for seed in range(400):
        rng = random.Random(seed)
        data = tomllib.loads(rng.choice(bases))
        for _ in range(rng.randint(1, 3)):
            model_mutations._change_data(rng, data)
        try:
            text = tomli_w.dumps(data)
        except (TypeError, ValueError):
            continue
        with warnings.catch_warnings():
            warnings.simplefilter("error", RuntimeWarning)
            try:
                initial_values(loads_model(text))
                outcomes["valid"] += 1
            except ModelError:
                outcomes["refused"] += 1
    assert outcomes["refused"] > 200 and outcomes["valid"] > 10


def test_set_on_the_command_line_names_the_orientation_key_and_refuses_unknown_names(tmp_path, capsys):
    path = _write(tmp_path, {})
    assert main(["check", path, "--set", "q_s={sequence = 'zx', angles = [0.1, 0.2]}", "--set", "u_s_wz=3"]) == 0
    capsys.readouterr()
    assert main(["check", path, "--set", "nosuch=1"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("flexkane: error: --set nosuch: expected a parameter") and "u_s_wx" in err
    assert "u_u_2, q_s), got 'nosuch'" in err     # the orientation table's key is listed last


def test_check_warns_of_normalized_euler_parameters(tmp_path, capsys):
    path = _write(tmp_path, {"initial": {"q_s_e0": 3, "q_s_e1": 0, "q_s_e2": 0, "q_s_e3": 4}})
    assert main(["check", path]) == 0
    out, err = capsys.readouterr()
    assert "valid (spatial" in out
    assert err == "flexkane: warning: initial Euler parameters of joint 's' had norm 5; normalized to 1\n"
    assert main(["check", _write(tmp_path, {})]) == 0
    assert capsys.readouterr().err == ""
