"""Arguments of the Python API are validated: a wrong one raises ModelError naming it, what was
expected and what was given, before any work is done.

The pipeline stages (simulate, derive, compile_model, load_results, run) are checked here too.
"""

import math

import numpy as np
import pytest

import flexkane
from flexkane.cli import main
from flexkane.errors import ModelError
from flexkane.model import Beam, Driver, Joint, RigidBody, ShapeSpec
from flexkane.model.paths import get_value, parse_path, set_value
from flexkane.model.validate import validate_run_arguments


def _raises(path: str, *texts: str):
    """Context manager: a ModelError at ``path`` whose message holds ``texts``."""
    class _Check:
        def __enter__(self):
            self.info = pytest.raises(ModelError)
            self.value = self.info.__enter__()
            return self

        def __exit__(self, *exc):
            handled = self.info.__exit__(*exc)
            error = self.value.value
            assert error.path == path, str(error)
            for text in texts:
                assert text in str(error), str(error)
            return handled
    return _Check()


@pytest.fixture
def arm():
    return flexkane.builtin_model("flexible-arm")


# ----------------------------------------------------------------------- models built in Python
def test_wrong_types_in_a_model_built_in_python_are_named_by_key_path(arm):
    cases = [
        ("bodies.hub.mass", "abc", "[kg]"),
        ("beams.link.n_modes", 2.5, "from 1 to 40, got"),
        ("beams.link.n_modes", True, "integer"),
        ("beams.link.EI", [20.0], "[N m^2]"),
        ("beams.link.geometric_stiffening", "yes", "true or false"),
        ("beams.link.damping", 0.02, "list of modal damping ratios"),
        ("joints.shoulder.type", "hinge", "'revolute'"),
        ("joints.shoulder.coordinates", "q", "list of 1"),
        ("simulation.t_end", "10 s", "end time [s]"),
        ("simulation.method", None, "'dop853'"),
        ("naming", "alphabetical", "'sequential'"),
        ("name", "", "non-empty"),
    ]
    for path, value, text in cases:
        model = arm.copy()
        set_value(model, path, value)
        with _raises(path, text):
            model.validate()


def test_parts_of_the_wrong_class_or_under_the_wrong_name_are_refused(arm):
    model = arm.copy()
    model.bodies["extra"] = {"mass": 1.0}
    with _raises("bodies.extra", "a RigidBody", "dict"):
        model.validate()
    model = arm.copy()
    model.beams["other"] = Beam("link2", 1.0, 1.0, 1.0, 1)
    with _raises("beams.other.name", "'other'", "link2"):
        model.validate()
    model = arm.copy()
    model.joints["shoulder"].torque = None
    model.joints["shoulder"].driver = {"speed": "1"}
    with _raises("joints.shoulder.driver", "coordinate"):
        model.validate()
    model = arm.copy()
    model.beams["link"].shape = "clamped-free"
    with _raises("beams.link.shape", "family"):
        model.validate()


def test_a_model_built_part_by_part_is_checked_like_a_file(arm):
    model = flexkane.Model(name="hand-built")
    model.bodies["hub"] = RigidBody("hub", 1.0, 0.1, {"P": (0.1, 0.0)})
    model.beams["arm"] = Beam("arm", 1.0, 10.0, 1.0, 2, ShapeSpec("clamped-free", roots=[1.875, -4.694]))
    model.joints["spin"] = Joint("spin", "revolute", "ground", "hub", driver=Driver(speed="2*t"))
    model.joints["clamp"] = Joint("clamp", "weld", "hub", "arm", parent_point="P")
    with _raises("beams.arm.shape.roots", "positive finite"):
        model.validate()
    model.beams["arm"].shape = ShapeSpec("clamped-free")
    model.initial["u_spin"] = 1.0
    with _raises("initial.u_spin", "prescribed by a driver"):
        model.validate()
    del model.initial["u_spin"]
    assert model.validate() is model


def test_derive_validates_its_model_first(arm):
    arm.beams["link"].rho = -1.0
    with _raises("beams.link.rho", "positive", "[kg/m]"):
        flexkane.derive(arm)


@pytest.mark.parametrize("n", [0, -1, 41, 201, 2.0, True, "3", None])
def test_with_modes_takes_an_integer_from_1_to_the_limit(arm, n):
    with _raises("n_modes", "from 1 to 40, got"):   # the library names the parameter; the CLI says --n-modes
        arm.with_modes(n)


def test_with_modes_refuses_a_count_other_than_the_typed_roots():
    model = flexkane.builtin_model("falling-beam")     # the notebook's lambda1 = 1.875, one root
    with _raises("beams.B.shape.roots", "2 roots"):
        model.with_modes(2)


# -------------------------------------------------------------------------------- key paths
def test_set_value_refuses_unknown_and_malformed_paths(arm):
    with _raises("beams.lnk.EI", "one of link", "did you mean 'link'?"):
        set_value(arm, "beams.lnk.EI", 1.0)
    with _raises("beams.link.EJ", "did you mean 'EI'?"):
        set_value(arm, "beams.link.EJ", 1.0)
    for bad in ("", "beams..EI", "beams.link.", "beams[x]", "a b", "x=1"):
        with pytest.raises(ModelError, match="key path"):
            set_value(arm, bad, 1.0)
    with pytest.raises(ModelError, match="key path"):
        parse_path(3)
    with _raises("beams.link", "not to a whole table"):
        set_value(arm, "beams.link", 3)
    with _raises("beams.link.damping[0]", "an index within a list of 0 items"):
        set_value(arm, "beams.link.damping[0]", 0.1)
    with _raises("beams.link.L.x", "plain value"):
        set_value(arm, "beams.link.L.x", 1.0)


def test_set_value_reaches_pair_components_and_shape_options(arm):
    set_value(arm, "bodies.hub.points.clamp[0]", 0.07)
    assert get_value(arm, "bodies.hub.points.clamp[0]") == 0.07
    assert isinstance(arm.bodies["hub"].points["clamp"], tuple)
    set_value(arm, "beams.link.shape.family", "clamped-free-tip-mass")
    set_value(arm, "beams.link.shape.mass_ratio", 0.5)
    set_value(arm, "beams.link.shape.inertia_ration", 0.0)
    with _raises("beams.link.shape.inertia_ration", "did you mean 'inertia_ratio'?"):
        arm.validate()


def test_a_bare_name_is_a_parameter_or_an_initial_condition_that_must_exist(arm):
    set_value(arm, "EI", 25.0)
    assert arm.parameters["EI"] == 25.0
    set_value(arm, "q_shoulder", 0.3)
    assert arm.validate().initial["q_shoulder"] == 0.3
    set_value(arm, "q_shouldr", 0.3)
    with _raises("initial.q_shouldr", "did you mean 'q_shoulder'?"):
        arm.validate()


# ------------------------------------------------------------------------- reading and writing
def test_reading_and_writing_model_files_check_their_arguments(tmp_path):
    with _raises("MODEL", "readable model file", "No such file"):
        flexkane.load_model(tmp_path / "missing.toml")
    with _raises("MODEL", "readable model file"):
        flexkane.load_model(tmp_path)
    with _raises("MODEL", "path of a model file"):
        flexkane.load_model(None)
    with _raises("<string>", "text of a model file", "bytes"):
        flexkane.loads_model(b"name = 'x'")
    with _raises("MODEL", "built-in model", "nope"):
        flexkane.builtin_model("nope")
    (tmp_path / "latin1.toml").write_bytes("name = 'caf\xe9'".encode("latin-1"))
    with pytest.raises(ModelError, match="UTF-8"):
        flexkane.load_model(tmp_path / "latin1.toml")
    with _raises("path", "writable", "missing-dir"):
        flexkane.save_model(flexkane.builtin_model("pendulum-beam"), tmp_path / "missing-dir" / "m.toml")


# ---------------------------------------------------------------------------- run arguments
@pytest.mark.parametrize("name, value, text", [
    ("t_end", -1.0, "end time [s]"), ("t_end", 0, "end time [s]"), ("t_end", "1", "end time [s]"),
    ("t_end", None, "end time [s]"), ("t_end", math.nan, "end time [s]"), ("dt_out", 0.0, "output interval [s]"),
    ("dt_out", math.inf, "output interval [s]"), ("rtol", -1e-8, "relative tolerance"),
    ("rtol", 1e-16, "relative tolerance"), ("rtol", 10.0, "relative tolerance"), ("atol", 0.0, "absolute tolerance"),
    ("method", "rk4", "'radau'"), ("max_steps", 0, "positive integer"), ("max_steps", 1.5, "positive integer"),
    ("progress", 3, "a function"),
])
def test_run_arguments_are_checked_before_a_run(name, value, text):
    arguments = {"t_end": 1.0, "dt_out": 0.01, "rtol": 1e-8, "atol": 1e-10, "method": "auto", "max_steps": None,
                 "progress": None, name: value}
    with pytest.raises(ModelError, match=name) as info:
        validate_run_arguments(**arguments)
    assert text in str(info.value)


@pytest.mark.parametrize("name, value", [("t_end", -1.0), ("dt_out", 0.0), ("rtol", -1.0), ("rtol", 10.0),
                                         ("atol", 0.0), ("method", "rk4"), ("max_steps", 0)])
def test_simulate_refuses_bad_numbers(torque_pendulum, name, value):
    _, compiled = torque_pendulum
    arguments = {"t_end": 0.1, "dt_out": 0.01, name: value}
    with pytest.raises(ModelError):
        flexkane.simulate(compiled, **arguments)


_SIMULATE = "simulation.simulate should call flexkane.model.validate.validate_run_arguments and check compiled/model"



@pytest.mark.parametrize("name, value", [("t_end", "1"), ("t_end", [1.0]), ("progress", 3), ("model", "x")])
def test_simulate_refuses_arguments_of_the_wrong_type(torque_pendulum, name, value):
    _, compiled = torque_pendulum
    arguments = {"t_end": 0.1, "dt_out": 0.01, name: value}
    with pytest.raises(ModelError):
        flexkane.simulate(compiled, **arguments)



def test_simulate_validates_the_model_it_is_given(torque_pendulum):
    model, compiled = torque_pendulum
    invalid = model.copy()
    invalid.parameters["m"] = -1.0
    with _raises("bodies.bob.mass", "positive"):
        flexkane.simulate(compiled, t_end=0.1, dt_out=0.01, model=invalid)



@pytest.mark.parametrize("stage", ["derive", "compile_model"])
def test_pipeline_stages_refuse_an_argument_of_the_wrong_kind(stage):
    with pytest.raises(ModelError):
        getattr(flexkane, stage)("falling-beam")



def test_load_results_of_a_missing_directory(tmp_path):
    with pytest.raises(ModelError):
        flexkane.load_results(tmp_path / "nothing")


def test_values_too_large_for_the_modal_constants_give_a_model_error():
    model = flexkane.builtin_model("pendulum-beam")
    model.parameters["EI"] = 1e308
    eom = flexkane.derive(model.validate())
    with pytest.raises(ModelError, match="beams.rod"):
        eom.constant_values(model)


def test_run_with_a_negative_end_time_exits_2(torque_pendulum, torque_pendulum_file, tmp_path, capsys):
    assert main(["run", str(torque_pendulum_file), "--t-end", "-1", "--out", str(tmp_path / "o"), "--quiet"]) == 2
    err = capsys.readouterr().err
    assert "Traceback" not in err and "t-end" in err and "positive" in err


def test_run_with_bad_arguments_creates_no_output_directory(torque_pendulum_file, tmp_path):
    assert main(["run", str(torque_pendulum_file), "--rtol", "10", "--out", str(tmp_path / "o"), "--quiet"]) == 2
    assert not (tmp_path / "o").exists()


def test_the_model_layer_accepts_numpy_numbers(arm):
    arm.beams["link"].EI = np.float64(30.0)
    arm.beams["link"].n_modes = np.int64(2)
    arm.bodies["hub"].points["clamp"] = (np.float32(0.05), np.int32(0))
    again = flexkane.loads_model(flexkane.dumps_model(arm.validate()))
    assert again.beams["link"].n_modes == 2 and again.beams["link"].EI == 30.0
