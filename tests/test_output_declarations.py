"""Typed outputs: every output of a model is declared where it is made, with its unit and group
(flexkane.model.columns); results.csv, the unit lookup and the plots read the declarations.

The column lists of results.csv below are those of flexkane before the outputs were declared (each
built-in model's, recorded from the version that recognised name prefixes): the declarations keep
them byte for byte.
"""

import json
from fractions import Fraction
from functools import cache

import numpy as np
import pytest

import flexkane
from flexkane.builtin import builtin_names
from flexkane.errors import ResultsError
from flexkane.model.columns import GROUPS, DuplicateColumnError, Output, Outputs
from flexkane.model.parameter_units import parse_unit
from flexkane.results import Results, load_results
from flexkane.run_manifest import RUN_OUTPUTS, manifest_of, units

#: results.csv's header of each built-in model, before the outputs were declared.
CSV_HEADERS = {
    "falling-beam": (
        "t,q1,q2,q3,q4,u1,u2,u3,u4,tip_B,kinetic,potential_gravity,strain,potential_springs,energy,"
        "work,energy_balance"
    ),
    "falling-beam-exact": (
        "t,q1,q2,q3,q4,u1,u2,u3,u4,tip_B,kinetic,potential_gravity,strain,potential_springs,energy,"
        "work,energy_balance"
    ),
    "flexible-arm": (
        "t,q_shoulder,q_link_1,q_link_2,q_link_3,u_shoulder,u_link_1,u_link_2,u_link_3,tip_link,"
        "effort_shoulder,kinetic,potential_gravity,strain,potential_springs,energy,work,"
        "energy_balance"
    ),
    "flexible-arm-lqr": (
        "t,q_shoulder,q_link_1,q_link_2,q_link_3,u_shoulder,u_link_1,u_link_2,u_link_3,tip_link,"
        "effort_shoulder,kinetic,potential_gravity,strain,potential_springs,energy,work,"
        "energy_balance"
    ),
    "flexible-arm-pd": (
        "t,q_shoulder,q_link_1,q_link_2,q_link_3,u_shoulder,u_link_1,u_link_2,u_link_3,tip_link,"
        "effort_shoulder,sensor_hub_angle,sensor_hub_rate,sensor_tip,sensor_root_strain,"
        "controller_reference,kinetic,potential_gravity,strain,potential_springs,energy,work,"
        "energy_balance"
    ),
    "flexible-arm-pid": (
        "t,q_shoulder,q_link_1,q_link_2,q_link_3,u_shoulder,u_link_1,u_link_2,u_link_3,"
        "error_integral,tip_link,effort_shoulder,load_disturbance_torque,sensor_tip,controller_error,"
        "controller_motor,kinetic,potential_gravity,strain,potential_springs,energy,work,"
        "energy_balance"
    ),
    "four-bar": (
        "t,q_crank,q_rocker,q_coupler,u_crank,kinetic,potential_gravity,strain,potential_springs,"
        "energy,work,energy_balance"
    ),
    "pendulum-beam": (
        "t,q_pivot,q_rod_1,q_rod_2,q_rod_3,u_pivot,u_rod_1,u_rod_2,u_rod_3,tip_rod,kinetic,"
        "potential_gravity,strain,potential_springs,energy,work,energy_balance"
    ),
    "robot-arm-3d": (
        "t,q_waist,q_shoulder,q_elbow,u_waist,u_shoulder,u_elbow,effort_waist,effort_shoulder,"
        "effort_elbow,yaw_column,pitch_column,roll_column,yaw_upper,pitch_upper,roll_upper,yaw_fore,"
        "pitch_fore,roll_fore,yaw_payload,pitch_payload,roll_payload,H_x,H_y,H_z,kinetic,"
        "potential_gravity,strain,potential_springs,energy,work,energy_balance"
    ),
    "robot-arm-3d-flexible": (
        "t,q_waist,q_shoulder,q_upper_y1,q_upper_y2,q_upper_z1,q_upper_z2,q_upper_t1,q_elbow,"
        "q_fore_y1,q_fore_y2,q_fore_z1,q_fore_z2,q_fore_t1,u_waist,u_shoulder,u_upper_y1,u_upper_y2,"
        "u_upper_z1,u_upper_z2,u_upper_t1,u_elbow,u_fore_y1,u_fore_y2,u_fore_z1,u_fore_z2,u_fore_t1,"
        "tip_upper_y,tip_upper_z,tip_fore_y,tip_fore_z,effort_waist,effort_shoulder,effort_elbow,"
        "yaw_column,pitch_column,roll_column,yaw_shoulder_hub,pitch_shoulder_hub,roll_shoulder_hub,"
        "yaw_elbow_motor,pitch_elbow_motor,roll_elbow_motor,yaw_payload,pitch_payload,roll_payload,"
        "twist_upper,twist_fore,H_x,H_y,H_z,kinetic,potential_gravity,strain,potential_springs,"
        "energy,work,energy_balance"
    ),
    "rotor-blade": (
        "t,q_rotor,q_blade_y1,q_blade_y2,q_blade_z1,q_blade_z2,q_blade_t1,u_blade_y1,u_blade_y2,"
        "u_blade_z1,u_blade_z2,u_blade_t1,tip_blade_y,tip_blade_z,effort_rotor,load_lift_fx,"
        "load_lift_fy,load_lift_fz,yaw_hub,pitch_hub,roll_hub,twist_blade,H_x,H_y,H_z,kinetic,"
        "potential_gravity,strain,potential_springs,energy,work,energy_balance"
    ),
    "slider-crank": (
        "t,q_slider,q_rod,q_rod_1,q_rod_2,s_rod_1,s_rod_2,u_rod_1,u_rod_2,v_rod_1,v_rod_2,tip_rod,"
        "effort_crank,kinetic,potential_gravity,strain,potential_springs,energy,work,energy_balance"
    ),
    "spacecraft-flexible-slew": (
        "t,q_float_x,q_float_y,q_float_z,q_float_e0,q_float_e1,q_float_e2,q_float_e3,q_panel_left_y1,"
        "q_panel_left_y2,q_panel_left_z1,q_panel_left_z2,q_panel_left_t1,q_panel_right_y1,"
        "q_panel_right_y2,q_panel_right_z1,q_panel_right_z2,q_panel_right_t1,u_float_vx,u_float_vy,"
        "u_float_vz,u_float_wx,u_float_wy,u_float_wz,u_panel_left_y1,u_panel_left_y2,u_panel_left_z1,"
        "u_panel_left_z2,u_panel_left_t1,u_panel_right_y1,u_panel_right_y2,u_panel_right_z1,"
        "u_panel_right_z2,u_panel_right_t1,tip_panel_left_y,tip_panel_left_z,tip_panel_right_y,"
        "tip_panel_right_z,load_slew_tx,load_slew_ty,load_slew_tz,yaw_bus,pitch_bus,roll_bus,"
        "twist_panel_left,twist_panel_right,quaternion_norm_float,H_x,H_y,H_z,kinetic,"
        "potential_gravity,strain,potential_springs,energy,work,energy_balance"
    ),
    "spacecraft-slew": (
        "t,q_float_x,q_float_y,q_float_z,q_float_e0,q_float_e1,q_float_e2,q_float_e3,u_float_vx,"
        "u_float_vy,u_float_vz,u_float_wx,u_float_wy,u_float_wz,load_slew_tx,load_slew_ty,"
        "load_slew_tz,yaw_bus,pitch_bus,roll_bus,yaw_panel_left,pitch_panel_left,roll_panel_left,"
        "yaw_panel_right,pitch_panel_right,roll_panel_right,quaternion_norm_float,H_x,H_y,H_z,"
        "kinetic,potential_gravity,strain,potential_springs,energy,work,energy_balance"
    ),
    "spin-up": (
        "t,q_hub,q_beam_1,q_beam_2,q_beam_3,q_beam_4,u_beam_1,u_beam_2,u_beam_3,u_beam_4,tip_beam,"
        "effort_hub,kinetic,potential_gravity,strain,potential_springs,energy,work,energy_balance"
    ),
    "spin-up-linear": (
        "t,q_hub,q_beam_1,q_beam_2,q_beam_3,q_beam_4,u_beam_1,u_beam_2,u_beam_3,u_beam_4,tip_beam,"
        "effort_hub,kinetic,potential_gravity,strain,potential_springs,energy,work,energy_balance"
    ),
    "two-link-flexible-arm": (
        "t,q_shoulder,q_upper_1,q_upper_2,q_elbow,q_fore_1,q_fore_2,u_shoulder,u_upper_1,u_upper_2,"
        "u_elbow,u_fore_1,u_fore_2,tip_upper,tip_fore,effort_shoulder,effort_elbow,kinetic,"
        "potential_gravity,strain,potential_springs,energy,work,energy_balance"
    ),
    "wind-mast": (
        "t,q_mast_1,q_mast_2,q_mast_3,q_mast_4,u_mast_1,u_mast_2,u_mast_3,u_mast_4,tip_mast,kinetic,"
        "potential_gravity,strain,potential_springs,energy,work,energy_balance"
    ),
}

#: Built-in models whose derivation takes tens of seconds on a loaded machine.
SPATIAL = {name for name in builtin_names() if flexkane.builtin_model(name).dimensions == 3}
MODELS = [pytest.param(name, marks=pytest.mark.slow) if name in SPATIAL else name for name in builtin_names()]

#: SI base dimensions of the unit names (rad is a ratio of lengths: dimensionless).
BASE = {"m": {"m": 1}, "kg": {"kg": 1}, "s": {"s": 1}, "rad": {}, "N": {"kg": 1, "m": 1, "s": -2},
        "J": {"kg": 1, "m": 2, "s": -2}, "W": {"kg": 1, "m": 2, "s": -3}, "Pa": {"kg": 1, "m": -1, "s": -2}}


@cache
def equations(name: str):
    return flexkane.derive(flexkane.builtin_model(name))


def dimension(unit: str) -> dict:
    """The SI base dimensions of a unit text (``"N m"`` -> ``{kg: 1, m: 2, s: -2}``)."""
    parsed = parse_unit(unit)
    assert parsed is not None, unit
    out: dict = {}
    for name, exponent in parsed.items():
        for base, power in BASE[name].items():
            out[base] = out.get(base, 0) + Fraction(exponent) * power
    return {k: v for k, v in sorted(out.items()) if v}


def times(*units: str) -> dict:
    """The dimension of the product of ``units``."""
    out: dict = {}
    for unit in units:
        for base, power in dimension(unit).items():
            out[base] = out.get(base, 0) + power
    return {k: v for k, v in sorted(out.items()) if v}


def run_columns(eom) -> list[str]:
    """results.csv's columns of a run of ``eom``, from its run manifest (as :func:`flexkane.simulate`
    reads the declarations: JSON and back) with every value zero."""
    manifest = manifest_of(eom)
    declared = [Output.from_json(entry) for entry in manifest["outputs"]]
    if any(d.name == "energy" for d in declared):
        declared += RUN_OUTPUTS
    results = Results(t=np.zeros(1), state=np.zeros((1, len(manifest["state_names"]))),
                      state_names=manifest["state_names"], outputs={d.name: np.zeros(1) for d in declared},
                      declared={d.name: d for d in declared})
    return results.csv_columns()


@pytest.mark.parametrize("name", MODELS)
def test_results_csv_has_the_columns_of_before_the_outputs_were_declared(name):
    assert ",".join(run_columns(equations(name))) == CSV_HEADERS[name]


@pytest.mark.parametrize("name", MODELS)
def test_every_output_of_a_built_in_model_is_declared_with_a_unit_and_a_group(name):
    eom = equations(name)
    declared = eom.output_declarations
    assert [d.name for d in declared] == eom.output_names
    for d in declared:
        assert d.group in GROUPS and d.description, d
        assert d.unit is not None and parse_unit(d.unit) is not None, d   # none left to guess
    unit = units(eom)
    assert all(unit[d.name] == d.unit for d in declared)


@pytest.mark.parametrize("name", MODELS)
def test_the_units_of_the_outputs_agree_with_dimensional_analysis(name):
    """Each declared unit against what physics makes it: energies J; the power times s an energy;
    an effort times its joint's speed, and a load's force times m/s (torque times rad/s), a power;
    positions m; angles, Euler parameters and slopes dimensionless; a tip deflection in the unit of
    its beam's modal coordinates, a twist in that of its torsion coordinates; a momentum kg times a
    speed, an angular momentum an energy times s; a dependent speed in its coordinate's speed unit."""
    eom = equations(name)
    chain = eom.chain
    speed = {c.owner: c.u.name for c in chain.coordinates if c.u is not None}
    unit = units(eom)
    for d in eom.output_declarations:
        dim = dimension(d.unit)
        if d.group == "energy":
            assert dim == dimension("kg m^2/s^2"), d
        elif d.group == "power":
            assert times(d.unit, "s") == dimension(unit["energy"]), d
        elif d.group in ("effort", "actuator"):
            assert times(d.unit, unit[speed[d.name.removeprefix("effort_")]]) == dimension("W"), d
        elif d.group == "load":
            assert dim in (dimension("N"), dimension("N m")), d
            rate = "m/s" if dim == dimension("N") else "rad/s"
            assert times(d.unit, rate) == dimension("W"), d
        elif d.group == "position":
            assert dim == dimension("m"), d
        elif d.group in ("frame_angle", "attitude", "orientation", "slope", "quaternion_norm"):
            assert dim == {}, d
        elif d.group in ("tip", "twist"):
            beam = next(b for b in chain.model.beams
                        if d.name in (f"{d.group}_{b}", *(f"{d.group}_{b}_{a}" for a in "yz")))
            roles = ("torsion",) if d.group == "twist" else ("mode", "mode_y", "mode_z")
            coordinate_units = {unit[c.q.name] for c in chain.coordinates if c.owner == beam and c.role in roles}
            assert coordinate_units == {d.unit}, d
        elif d.group == "momentum":
            assert dim in (times("kg", "m/s"), times("kg m^2", "rad/s")), d
        elif d.group == "angular_momentum":
            assert dim == times(unit["energy"], "s"), d
        elif d.group == "dependent_speed":
            assert d.unit == unit[d.name] and d.unit.endswith("/s"), d
        elif d.group == "constraint":
            assert dim in (dimension("m"), {}), d
        else:
            assert d.group in ("sensor", "controller"), d


def test_a_name_made_twice_is_refused_where_it_is_made_saying_what_both_are():
    outputs = Outputs()
    outputs.add("x_cm", 1, "m", "position", "x of the system's mass centre")
    with pytest.raises(DuplicateColumnError, match=r"'x_cm' was made twice, as x of the system's mass centre \[m\] "
                                                    r"and as x of body 'cm's mass centre \[m\]"):
        outputs.add("x_cm", 2, "m", "position", "x of body 'cm's mass centre")
    assert dict(outputs) == {"x_cm": 1}


def test_an_output_without_a_unit_or_of_an_unknown_group_is_refused():
    with pytest.raises(ValueError, match="has no unit"):
        Output("energy", None, None, "energy")
    with pytest.raises(ValueError, match="not one of"):
        Output("energy", None, "J", "energies")
    assert Output("controller_c", None, None, "controller").unit is None   # the model's expressions fix none


def test_declarations_are_written_to_results_npz_and_read_back(tmp_path):
    t = np.array([0.0, 0.5])
    declared = {"tip_b": Output("tip_b", None, "m", "tip", "deflection of beam 'b'"),
                "energy": Output("energy", None, "J", "energy", "the total energy")}
    results = Results(t=t, state=np.zeros((2, 1)), state_names=["q"], outputs={"energy": t, "tip_b": 2 * t},
                      declared=declared)
    results.write(tmp_path)
    back = load_results(tmp_path)
    assert back.declared == declared and back.csv_columns() == ["t", "q", "tip_b", "energy"]
    assert (tmp_path / "results.csv").read_text().splitlines()[0] == "t,q,tip_b,energy"


def test_damaged_declarations_and_units_in_results_npz_are_refused(tmp_path):
    t = np.array([0.0, 0.5])
    Results(t=t, state=np.zeros((2, 1)), state_names=["q"], outputs={"energy": t},
            declared={"energy": Output("energy", None, "J", "energy")}).write(tmp_path)
    with np.load(tmp_path / "results.npz") as data:
        arrays = {k: data[k] for k in data.files}
    for bad, says in (('[["energy", "J", "energies", ""]]', "known group"), ('[["power", "W", "power", ""]]',
                                                                               "not an output of the file"),
                      ('[["energy", 3, "energy", ""]]', "not a text"), ('[1]', "name, unit, group")):
        np.savez(tmp_path / "results.npz", **{**arrays, "output_declarations": np.array(bad)})
        with pytest.raises(ResultsError, match=says):
            load_results(tmp_path)
    for bad in ('{"x": "m"}', '{"q": 1}', '["q"]'):
        np.savez(tmp_path / "results.npz", **{**arrays, "state_units": np.array(bad)})
        with pytest.raises(ResultsError, match="state_units"):
            load_results(tmp_path)


def test_a_run_writes_the_recorded_columns_and_its_declarations(tmp_path):
    """A real run of a model with a driver, a load, a sensor and controllers: results.csv's header is
    the recorded one, results.npz holds the declarations of the outputs and of the run's work."""
    model = flexkane.builtin_model("flexible-arm-pid")
    results = flexkane.simulate(flexkane.compile_model(flexkane.derive(model)), t_end=0.02, dt_out=0.01, model=model)
    results.write(tmp_path)
    assert (tmp_path / "results.csv").read_text().splitlines()[0] == CSV_HEADERS["flexible-arm-pid"]
    back = load_results(tmp_path)
    assert back.declared["controller_motor"].unit == "N m" and back.declared["work"].group == "energy"
    assert back.outputs_of("tip") == ["tip_link"] and back.outputs_of("actuator") == ["effort_shoulder"]
    assert back.units == results.units and back.state_units == results.state_units


def test_the_units_of_results_csv_are_in_a_file_beside_it_in_the_order_of_its_columns(tmp_path):
    """results.units.json maps every column of results.csv, in order, to its unit: the state's by the
    coordinates' roles (an angle rad, a modal coordinate m), the outputs' as declared."""
    model = flexkane.builtin_model("flexible-arm")
    results = flexkane.simulate(flexkane.compile_model(flexkane.derive(model)), t_end=0.01, dt_out=0.01, model=model)
    results.write(tmp_path)
    header = (tmp_path / "results.csv").read_text().splitlines()[0].split(",")
    units = json.loads((tmp_path / "results.units.json").read_text())
    assert list(units) == header
    assert units == {"t": "s", "q_shoulder": "rad", "q_link_1": "m", "q_link_2": "m", "q_link_3": "m",
                     "u_shoulder": "rad/s", "u_link_1": "m/s", "u_link_2": "m/s", "u_link_3": "m/s", "tip_link": "m",
                     "effort_shoulder": "N m", **dict.fromkeys(("kinetic", "potential_gravity", "strain",
                                                                "potential_springs", "energy", "work",
                                                                "energy_balance"), "J")}
    assert load_results(tmp_path).units["q_link_1"] == "m"


def test_a_dataframe_of_the_results_carries_the_units_of_its_columns():
    pandas = pytest.importorskip("pandas")
    t = np.array([0.0, 0.5])
    results = Results(t=t, state=np.zeros((2, 1)), state_names=["q"], outputs={"energy": t}, state_units={"q": "rad"},
                      declared={"energy": Output("energy", None, "J", "energy")})
    frame = results.to_dataframe()
    assert isinstance(frame, pandas.DataFrame) and frame.attrs["units"] == {"t": "s", "q": "rad", "energy": "J"}


@pytest.mark.parametrize("name", ["four-bar", "spacecraft-slew"])
def test_a_linear_model_leaves_out_the_energies_momenta_and_loop_columns_by_their_groups(name):
    """Planar and spatial alike: no energy, power, linear or angular momentum (``p_z`` and ``H_x`` of a
    spatial model too), loop residual or dependent speed is an output of the linear model."""
    from flexkane.analysis.linear_model import linear_outputs

    eom = equations(name)
    kept = linear_outputs(eom)
    groups = {d.name: d.group for d in eom.output_declarations}
    assert kept == [n for n in eom.output_names if groups[n] not in
                    ("energy", "power", "momentum", "angular_momentum", "constraint", "dependent_speed")]
    assert not {"energy", "p_x", "p_z", "H_x", "h_cm", "constraint_loop_1", "u_coupler"} & set(kept)
    assert {"theta_crank", "x_cm"} <= set(kept) if name == "four-bar" else {"yaw_bus", "e0_bus", "z_cm"} <= set(kept)


def test_a_driver_effort_and_an_actuator_torque_are_plotted_each_under_its_own_title(tmp_path, monkeypatch):
    from flexkane import plots

    titles = {}
    save = plots._save
    monkeypatch.setattr(plots, "_save", lambda fig, path: (titles.setdefault(path.name, fig.axes[0].get_title()),
                                                           save(fig, path))[1])
    t = np.linspace(0.0, 1.0, 20)
    declared = {"effort_hub": Output("effort_hub", None, "N m", "effort"),
                "effort_arm": Output("effort_arm", None, "N m", "actuator"),
                "effort_slide": Output("effort_slide", None, "N", "actuator")}
    results = Results(t=t, state=np.zeros((20, 0)), state_names=[], outputs={n: np.sin(t) for n in declared},
                      declared=declared)
    plots.write_plots(results, {}, tmp_path, "m")
    assert titles == {"effort_hub.png": "m: driver effort", "effort_arm.png": "m: actuator torque",
                      "effort_slide.png": "m: actuator force"}
