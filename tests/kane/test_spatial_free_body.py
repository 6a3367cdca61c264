"""A rigid body on a free joint (six degrees of freedom, Euler parameters), compiled once.

Without gravity or loads its energy and its angular momentum vector about the mass centre are
conserved, and rotation about the axis of the intermediate principal moment is unstable while
rotation about the largest or smallest is stable (Euler's equations). Under gravity its mass centre
falls at exactly g whatever it spins. The quaternion norm stays 1 to the solver's tolerance.
"""

import numpy as np
import pytest

import flexkane
from flexkane.model import loads_model

FREE_BODY = """
name = "free-body"
dimensions = 3

[parameters]
g = 0.0

[bodies.B]
mass = 2.5
inertia = [[1.0, 0.0, 0.0], [0.0, 2.0, 0.0], [0.0, 0.0, 3.0]]
points = { corner = [0.3, -0.2, 0.1] }

[joints.float]
type = "free"
parent = "ground"
child = "B"
child_point = "corner"

[gravity]
g = "g"
direction = [0, 0, -1]

[initial]
q_float = { sequence = "zyx", angles = [0.4, -0.3, 1.1] }
u_float_vx = 0.2
u_float_vy = -0.1
u_float_vz = 0.3
"""


@pytest.fixture(scope="module")
def compiled():
    model = loads_model(FREE_BODY)
    return model, flexkane.compile_model(flexkane.derive(model, cache=False))


def _run(compiled, t_end, rtol=1e-12, atol=1e-12, **values):
    model, module = compiled
    return flexkane.simulate(module, model=model.with_values(values), t_end=t_end, dt_out=t_end / 200,
                             rtol=rtol, atol=atol)


def _spin(axis: int, rate: float, perturbation: float) -> dict:
    """Angular velocity mostly about one body axis, with small components about the others."""
    w = np.full(3, perturbation)
    w[axis] = rate
    return {f"u_float_w{a}": float(c) for a, c in zip("xyz", w)}


def test_torque_free_body_conserves_energy_and_angular_momentum(compiled):
    res = _run(compiled, 10.0, **_spin(1, 1.5, 0.3))
    energy = res.outputs["energy"]
    H = np.array([res.outputs[f"H_{a}"] for a in "xyz"])
    assert np.abs(energy - energy[0]).max() <= 1e-10 * abs(energy[0])
    assert np.abs(H - H[:, :1]).max() <= 1e-10 * np.linalg.norm(H[:, 0])
    p = np.array([res.outputs[f"p_{a}"] for a in "xyz"])
    assert np.abs(p - p[:, :1]).max() <= 1e-10 * np.linalg.norm(p[:, 0])
    assert np.abs(res.outputs["quaternion_norm_float"]).max() <= 1e-9
    # the body tumbles: the angular velocity along its axes changes a lot while H stays put
    w_y = res.state[:, res.state_names.index("u_float_wy")]
    assert w_y.min() < 0 < w_y.max()


@pytest.mark.parametrize("axis, stable", [(0, True), (1, False), (2, True)],
                         ids=["smallest", "intermediate", "largest"])
def test_rotation_about_the_intermediate_principal_axis_is_unstable(compiled, axis, stable):
    res = _run(compiled, 20.0, rtol=1e-10, atol=1e-12, **_spin(axis, 2.0, 1e-4))
    others = np.delete(np.array([res.state[:, res.state_names.index(f"u_float_w{a}")] for a in "xyz"]), axis, 0)
    growth = np.abs(others).max() / 1e-4
    if stable:
        assert growth < 10
    else:
        assert growth > 1000


def test_mass_centre_of_a_spinning_free_body_falls_at_g(compiled):
    g = 9.81
    res = _run(compiled, 2.0, g=g, **_spin(0, 3.0, 0.5))
    t = res.t
    z = res.outputs["z_cm"]
    z0, vz0 = z[0], res.outputs["p_z"][0] / 2.5
    assert np.abs(z - (z0 + vz0 * t - g * t ** 2 / 2)).max() <= 1e-9
    for a in "xy":    # no horizontal force: uniform motion
        x = res.outputs[f"{a}_cm"]
        v = res.outputs[f"p_{a}"][0] / 2.5
        assert np.abs(x - (x[0] + v * t)).max() <= 1e-9


def test_a_loose_tolerance_that_lets_the_quaternion_norm_drift_is_warned(compiled):
    tight = _run(compiled, 5.0, **_spin(1, 6.0, 3.0))
    assert not [w for w in tight.warnings if "Euler parameters" in w]
    loose = _run(compiled, 5.0, rtol=1e-3, atol=1e-3, **_spin(1, 6.0, 3.0))
    assert np.abs(loose.outputs["quaternion_norm_float"]).max() > 1e-6
    assert [w for w in loose.warnings if "joint 'float'" in w and "Euler parameters" in w]


def test_orientation_outputs_of_a_body_are_its_euler_parameters_and_yaw_pitch_roll(compiled):
    res = _run(compiled, 1.0, **_spin(2, 1.0, 0.2))
    e = np.array([res.state[:, res.state_names.index(f"q_float_e{k}")] for k in range(4)])
    assert np.abs(np.array([res.outputs[f"e{k}_B"] for k in range(4)]) - e).max() <= 1e-14
    # the initial orientation was given as the body-fixed sequence zyx (yaw, pitch, roll)
    assert np.allclose([res.outputs[a][0] for a in ("yaw_B", "pitch_B", "roll_B")], [0.4, -0.3, 1.1], atol=1e-12)


def test_a_spatial_model_runs_from_the_command_line(compiled, tmp_path):
    """``flexkane run`` of a spatial model file (the structure compiled above is taken from the cache):
    the state has 7 coordinates and 6 speeds, equations.md lists the Euler parameters."""
    from flexkane.cli import main

    path = tmp_path / "free-body.toml"
    path.write_text(FREE_BODY)
    out = tmp_path / "run"
    assert main(["run", str(path), "--out", str(out), "--quiet", "--no-plots", "--t-end", "0.5"]) == 0
    header = (out / "results.csv").read_text().splitlines()[0].split(",")
    assert header[1:14] == ["q_float_x", "q_float_y", "q_float_z", "q_float_e0", "q_float_e1", "q_float_e2",
                            "q_float_e3", "u_float_vx", "u_float_vy", "u_float_vz", "u_float_wx", "u_float_wy",
                            "u_float_wz"]
    equations = (out / "equations.md").read_text()
    assert "(none: an Euler parameter)" in equations and "Partial velocities" in equations
