"""Operating points: equilibria found or refused, rest of free-floating chains, steady spins."""

import numpy as np
import pytest
import sympy as sp

import flexkane
from flexkane.errors import ModelError
from flexkane.analysis import Linearization, NoEquilibriumError, linearize, modal_analysis
from flexkane.modes import get_family

# free fall under gravity; a crank driven at a constant speed
EXPECTED_WITHOUT_EQUILIBRIUM = {"falling-beam", "falling-beam-exact", "slider-crank"}


def without_gravity(name):
    model = flexkane.builtin_model(name)
    model.parameters["g"] = 0
    return model


@pytest.mark.parametrize("name", [pytest.param(n, marks=pytest.mark.slow) if n == "robot-arm-3d-flexible" else n
                                  for n in flexkane.builtin_names()])   # 13 speeds: 17 s on CI
def test_every_builtin_example_linearizes_or_reports_that_it_has_no_equilibrium(name):
    model = flexkane.builtin_model(name)
    # models with controller states (flexible-arm-pid) linearize too, about an equilibrium of (q, z):
    # their state (dq, du, dz) has nz more eigenvalues, each real one counted 1/2 below
    if name in EXPECTED_WITHOUT_EQUILIBRIUM:
        with pytest.raises(NoEquilibriumError, match="has no equilibrium"):
            linearize(model)
        return
    linear = linearize(model)
    modal = modal_analysis(linear)
    assert linear.residual <= 1e-6
    assert sum(1 if m.kind in ("rigid", "oscillatory") else 0.5 for m in modal.modes) == linear.n + linear.nz / 2
    assert np.all(np.isfinite(modal.frequencies)) and np.all(modal.frequencies > 0)


def test_no_equilibrium_is_a_model_error_that_says_why():
    with pytest.raises(ModelError) as info:
        linearize(flexkane.builtin_model("falling-beam-exact"))
    message = str(info.value)
    assert "no equilibrium" in message and "free fall" in message and "--set g=0" in message
    with pytest.raises(NoEquilibriumError, match="not in equilibrium at rest"):
        linearize(flexkane.builtin_model("falling-beam-exact"), about="rest")


def test_free_floating_chain_at_rest_has_three_rigid_body_modes():
    modal = modal_analysis(linearize(without_gravity("falling-beam-exact").with_modes(2), about="rest"))
    assert len(modal.rigid) == 3
    assert [m.kind for m in modal.elastic] == ["oscillatory"] * 2
    # the rigid-body modes move q1, q2, q3 only (translations and rotation, no deformation)
    shapes = np.array([m.shape for m in modal.rigid])
    np.testing.assert_allclose(shapes[:, 3:], 0.0, atol=1e-12)
    assert np.linalg.matrix_rank(shapes[:, :3]) == 3


def test_free_floating_beam_on_a_very_heavy_body_vibrates_like_a_cantilever():
    model = without_gravity("falling-beam-exact").with_modes(3)
    model.parameters["mR"] = 1e9
    modal = modal_analysis(linearize(model, about="rest"))
    values = {s.name: v for s, v in flexkane.derive(model).constant_values().items()}
    p = get_family("clamped-free").frequencies(3, values["L"], values["EI"], values["ro"])
    np.testing.assert_allclose(modal.frequencies, p, rtol=1e-7)


def test_pendulum_beam_hangs_down_and_swings_at_the_rigid_pendulum_frequency():
    model = flexkane.builtin_model("pendulum-beam")
    model.parameters["EI"] = 1e7            # nearly rigid: sqrt(3 g / (2 L)) for a uniform rod
    linear = linearize(model)                # searched from q_pivot = 1.2
    np.testing.assert_allclose(linear.q0, 0.0, atol=1e-12)
    first = modal_analysis(linear).frequencies[0]
    assert first == pytest.approx(np.sqrt(3 * 9.81 / 2), rel=1e-5)


def test_inverted_pendulum_equilibrium_is_found_and_is_unstable():
    model = flexkane.builtin_model("pendulum-beam")
    model.initial["q_pivot"] = 3.0
    linear = linearize(model)
    assert linear.q0[0] == pytest.approx(np.pi, abs=1e-10)
    modal = modal_analysis(linear)
    assert not modal.stable
    assert [m.kind for m in modal.modes].count("divergent") == 1


def test_four_bar_oscillates_about_its_hanging_equilibrium_at_the_energy_frequency():
    """One degree of freedom: w^2 = V''(theta) / m(theta), V the potential and m the generalized mass
    along the closed loop (2 T at unit crank speed), by finite differences of the energy outputs."""
    model = flexkane.builtin_model("four-bar")
    lin = Linearization(model)
    eom = lin.eom
    values = eom.constant_values()
    potential = sp.lambdify(eom.q, eom.outputs["potential_gravity"].xreplace(values))
    kinetic = sp.lambdify(eom.q + eom.u, eom.outputs["kinetic"].xreplace(values))
    q_start = eom.initial_state()[:len(eom.q)]

    def closed(theta):
        q = q_start.copy()
        q[eom.q.index(lin.q[0])] = theta
        return eom.project_coordinates(q, values)

    for start, kind in ((4.0, "oscillatory"), (1.0, "divergent")):     # hanging, and upside down
        linear = lin.at(q_start=[start])
        assert linear.coordinates == ["q_crank"] and set(linear.dropped) == {"q_coupler", "q_rocker"}
        theta, h = linear.q0[0], 1e-4
        stiffness = (potential(*closed(theta + h)) - 2 * potential(*closed(theta))
                     + potential(*closed(theta - h))) / h ** 2
        mass = 2 * kinetic(*closed(theta), 1.0)
        mode = [m for m in modal_analysis(linear).modes if m.kind == kind][0]
        omega_squared = mode.omega ** 2 if kind == "oscillatory" else -mode.eigenvalue.real ** 2
        assert omega_squared == pytest.approx(stiffness / mass, rel=1e-6)


def test_spin_is_refused_when_the_hub_angle_appears_in_the_equations():
    with pytest.raises(NoEquilibriumError, match="no steady spin"):
        linearize(flexkane.builtin_model("pendulum-beam"), about="spin", spin=2.0)


def test_driven_hub_moving_at_t0_has_no_equilibrium():
    with pytest.raises(NoEquilibriumError, match="driven at"):
        Linearization(flexkane.builtin_model("spin-up-linear"), t0=5.0)


def test_spin_of_an_undriven_hub_replaces_its_torque_by_the_prescribed_speed():
    linear = linearize(flexkane.builtin_model("flexible-arm"), about="spin", spin=3.0)
    assert linear.hub == "shoulder" and linear.spin == 3.0
    assert linear.coordinates == ["q_link_1", "q_link_2", "q_link_3"]
    assert linear.inputs == []                      # the shoulder torque is the driver's effort now
    assert any("not an input" in note for note in linear.notes)


@pytest.mark.parametrize("kwargs, path", [({"about": "spin"}, "--spin"), ({"spin": 1.0}, "--spin"),
                                           ({"about": "sideways"}, "--about"),
                                           ({"about": "spin", "spin": 1.0, "hub": "nope"}, "--hub")])
def test_invalid_operating_point_arguments_name_the_option(kwargs, path):
    with pytest.raises(ModelError) as info:
        linearize(flexkane.builtin_model("flexible-arm"), **kwargs)
    assert info.value.path == path
