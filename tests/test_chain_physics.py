"""Physics of general chains (issue 3): conservation, power balance, momentum, API equivalence."""

import numpy as np
import pytest
from scipy.integrate import cumulative_trapezoid

import flexkane
from flexkane.model import Beam, Gravity, Joint, Model, RigidBody, ShapeSpec


def run(model, t_end, dt_out=1e-3, rtol=1e-10, atol=1e-12):
    compiled = flexkane.compile_model(flexkane.derive(model))
    return flexkane.simulate(compiled, t_end=t_end, dt_out=dt_out, rtol=rtol, atol=atol, model=model)


def test_flexible_pendulum_conserves_energy():
    res = run(flexkane.builtin_model("pendulum-beam"), t_end=2.0)
    e = res["energy"]
    assert np.abs(res["u_rod_1"]).max() > 1e-3          # the beam does bend
    assert np.abs(e - e[0]).max() < 1e-8 * np.abs(res["kinetic"]).max()


@pytest.mark.parametrize("damping", [0.0, 0.05])
def test_driven_damped_arm_power_balance(damping):
    model = flexkane.builtin_model("flexible-arm")
    if damping:
        model.beams["link"].damping = [damping]
        model.joints["shoulder"].damping = 0.02
    res = run(model, t_end=1.0, dt_out=2.5e-4)
    e = res["energy"]
    work = cumulative_trapezoid(res["power_nonconservative"], res.t, initial=0.0)
    scale = np.abs(e).max()
    assert scale > 0.1
    assert np.abs(e - e[0] - work).max() < 2e-6 * scale
    # the work integrated with the motion: the balance is the solver's error (rtol 1e-10)
    assert np.abs(res["energy_balance"]).max() < 1e-9 * scale
    assert np.abs(res["work"] - work).max() < 2e-6 * scale
    if damping:
        assert work[-1] < np.trapezoid(np.clip(res["power_nonconservative"], 0, None), res.t)


def test_hub_and_beam_keep_angular_momentum_about_the_axis_without_torque():
    model = flexkane.builtin_model("flexible-arm")
    model.joints["shoulder"].torque = None
    model.initial = {"u_shoulder": 2.0, "q_link_1": 0.02}
    res = run(model, t_end=1.0)
    h = res["h_o"]
    assert np.abs(res["u_link_1"]).max() > 0.05
    assert np.abs(h - h[0]).max() < 1e-8 * abs(h[0])


def chapter_model_by_api(n_modes=2) -> Model:
    """The chapter's falling-beam-exact built in Python rather than read from its file."""
    model = Model(name="falling-beam-exact", naming="sequential",
                  parameters={"L": 1.0, "b": 0.1, "c": 0.2, "d": 0.3, "mR": 1.0, "ro": 0.21991, "EI": 35.3,
                              "Iz": "mR*(c**2 + d**2)/12", "g": 9.81})
    model.bodies["RB"] = RigidBody("RB", "mR", "Iz", {"Q": ("b", 0)})
    model.beams["B"] = Beam("B", "L", "EI", "ro", n_modes, ShapeSpec("clamped-free"))
    model.joints["free"] = Joint("free", "free", "ground", "RB")
    model.joints["clamp"] = Joint("clamp", "weld", "RB", "B", parent_point="Q")
    model.gravity = Gravity("g", (0, -1))
    model.initial = {"q3": 1.0, "q4": 0.0001}
    return model.validate()


def test_chapter_example_through_the_python_api_gives_the_file_model_trajectories():
    by_api = run(chapter_model_by_api(), t_end=0.5)
    from_file = run(flexkane.builtin_model("falling-beam-exact").with_modes(2), t_end=0.5)
    assert by_api.state_names == from_file.state_names
    np.testing.assert_array_equal(by_api.state, from_file.state)


SPRUNG_BODY = """
name = "sprung-body"
[parameters]
m = 2.0
J = 0.1
k = 80.0
c = 0.0
g = 9.81
[bodies.box]
mass = "m"
inertia = "J"
points = { hook = [0.2, 0.1] }
[joints.free]
type = "free"
parent = "ground"
child = "box"
[springs.hanger]
body_a = "ground"
position_a = [0, 1]
body_b = "box"
point_b = "hook"
stiffness = "k"
damping = "c"
rest_length = 0.5
[gravity]
g = "g"
direction = [0, -1]
[initial]
q_free_x = 0.3
u_free_angle = 1.0
"""


@pytest.mark.parametrize("damping", [0.0, 0.8])
def test_body_on_a_spring_between_points_balances_energy(damping):
    model = flexkane.loads_model(SPRUNG_BODY)
    model.parameters["c"] = damping
    res = run(model, t_end=2.0, dt_out=5e-4)
    e = res["energy"]
    work = cumulative_trapezoid(res["power_nonconservative"], res.t, initial=0.0)
    assert np.abs(res["q_free_angle"]).max() > 0.3
    assert np.abs(e - e[0] - work).max() < 1e-6 * np.abs(e).max()
    if damping:
        assert work[-1] < -0.1
    else:
        assert np.abs(e - e[0]).max() < 1e-8 * np.abs(e).max()
