"""Linearization of spatial chains with loop constraints: rotation coordinates, then the loops closed.

Physics is the oracle: the axis pendulum (a body on a spherical joint whose point P is held on a
ground line, so that it swings about the horizontal axis through the pivot and P) oscillates at the
physical pendulum's frequency ``omega^2 = m g rho / I_n``; the RSSR four-bar (slow) oscillates about
its hanging equilibrium and diverges from the upright one at ``omega^2 = V''/m`` along its
one-degree-of-freedom path, both from the closed-form kinematics; a planar four-bar run through the
spatial engine has the planar engine's eigenvalues.
"""

from __future__ import annotations

import pathlib

import numpy as np
import pytest
from scipy.optimize import brentq

import flexkane
from flexkane.analysis import Linearization, modal_analysis
from flexkane.analysis.reduction import loop_columns
from flexkane.model import as_spatial, load_model

LOOPS = pathlib.Path(__file__).parents[1] / "kane" / "spatial_loops"


@pytest.fixture(scope="module")
def axis_pendulum():
    return Linearization(load_model(LOOPS / "axis_pendulum.toml"))


def _eigenvalues(linear) -> np.ndarray:
    return np.sort_complex(np.linalg.eigvals(linear.state_space()[0]))


def test_axis_pendulum_swings_at_the_physical_pendulum_frequency(axis_pendulum):
    """P - O = [l, 0, 0] in the body and |P| = l on the line x = d, z = 0: the axis n through O and P
    is horizontal and body-fixed (the body's x axis); the mass centre is at r = -O from the pivot,
    rho = sqrt(r_y^2 + r_z^2) from the axis, and I_n = I_xx + m rho^2 about it."""
    m, g, I_xx = 1.2, 9.81, 0.02
    r = -np.array([-0.2, -0.1, 0.05])
    rho = np.hypot(r[1], r[2])
    expected = np.sqrt(m * g * rho / (I_xx + m * rho ** 2))
    linear = axis_pendulum.at()
    assert linear.coordinates == ["rx_pivot"]       # the spin about the pendulum's own axis
    assert set(linear.dropped) == {"ry_pivot", "rz_pivot"}
    assert linear.dependent_map.shape == (2, 1)
    modes = modal_analysis(linear).modes
    assert [mode.kind for mode in modes] == ["oscillatory"]
    assert modes[0].omega == pytest.approx(expected, rel=1e-9)
    assert any("ry_pivot, rz_pivot follow" in note for note in linear.notes)


def test_axis_pendulum_configuration_keeps_the_loop_closed_and_turns_about_the_axis(axis_pendulum):
    """A perturbation of the linear model's coordinate turns the body about the pendulum axis: the
    loop stays closed, the Euler parameters of unit norm, the turn's angle is the perturbation."""
    lin = axis_pendulum
    linear = lin.at()
    eom = lin.eom
    values = eom.constant_values()
    gaps = [eom.outputs[f"constraint_line_{k}"].xreplace(values) for k in (1, 2)]
    e0 = lin.full_operating_point(linear)
    for delta in (1e-3, 0.2):
        config = lin.configuration(linear, linear.q0 + delta)
        e = np.array([config[q] for q in lin.q_all])
        assert np.linalg.norm(e) == pytest.approx(1.0, abs=1e-12)
        assert max(abs(float(gap.xreplace(config))) for gap in gaps) < 1e-10
        # relative turn e0^-1 (x) e: angle delta about the body's x axis (the pendulum axis)
        a0, av = e0[0], -e0[1:]
        turn = np.concatenate([[a0 * e[0] - av @ e[1:]], a0 * e[1:] + e[0] * av + np.cross(av, e[1:])])
        turn *= np.sign(turn[0])
        assert 2 * np.arctan2(np.linalg.norm(turn[1:]), turn[0]) == pytest.approx(delta, rel=1e-9)
        np.testing.assert_allclose(turn[1:] / np.linalg.norm(turn[1:]), [1, 0, 0], atol=1e-9)


def test_q_start_of_a_spatial_loop_takes_all_coordinates_or_the_independent_ones(axis_pendulum):
    """As for planar loops, q_start gives all coordinates or only those the loop closure does not
    solve for: the axis pendulum's four Euler parameters are all closed by the loop, so it has none
    (the loop closed from the model's guess); any other count is refused, naming both."""
    lin = axis_pendulum
    assert len(lin.q_all) == 4
    default = lin.operating_point().q
    np.testing.assert_allclose(lin.operating_point(q_start=[]).q, default, rtol=0, atol=1e-15)
    np.testing.assert_allclose(lin.operating_point(q_start=default).q, default, rtol=0, atol=1e-15)
    with pytest.raises(flexkane.ModelError, match="q_start: expected 0 or 4 coordinates"):
        lin.operating_point(q_start=[1.0])


@pytest.mark.slow
def test_q_start_of_independent_coordinates_places_a_free_block_on_its_line():
    """Without gravity every closed configuration of the block on a line is an equilibrium, so the
    operating point is the start: the height z and the orientation given (five independent
    coordinates), x and y closed so that the point P lies on the line."""
    lin = Linearization(load_model(LOOPS / "block_on_line.toml"))
    names = [q.name for q in lin.q_all]
    e = np.array([np.cos(0.3), 0.0, np.sin(0.3), 0.0])         # a turn of 0.6 rad about y
    check = lin.operating_point(q_start=[0.25, *e])
    assert check.ok
    q = dict(zip(names, check.q))
    assert q["q_float_z"] == 0.25
    np.testing.assert_allclose([q[f"q_float_e{i}"] for i in range(4)], e, rtol=0, atol=1e-15)
    turn = _turn([0, 1, 0], 0.6)
    P = np.array([q["q_float_x"], q["q_float_y"], q["q_float_z"]]) + turn @ np.array([0.05, -0.02, 0.1])
    np.testing.assert_allclose(P[:2], [0.2, 0.1], rtol=0, atol=1e-13)
    with pytest.raises(flexkane.ModelError, match="5 or 7 coordinates"):
        lin.operating_point(q_start=[0.25])


def test_loop_columns_pair_reduced_coordinates_with_speeds():
    speeds = ["u_crank", "u_rocker", "u_c_wx", "u_c_wy", "u_c_wz"]
    assert loop_columns(speeds, ["u_crank", "u_c_wx"], ["u_c_wy", "u_rocker", "u_c_wz"]) == ([0, 2], [1, 3, 4])
    with pytest.raises(flexkane.ModelError, match="one rotation or plain coordinate per"):
        loop_columns(speeds, ["u_crank"], ["u_rocker"])


@pytest.mark.slow
def test_planar_four_bar_through_the_spatial_engine_has_the_planar_eigenvalues():
    """The same equilibrium (the planar one, on its assembly branch, starts the spatial search): the
    same eigenvalues, hanging (oscillating) and upright (divergent)."""
    planar = flexkane.builtin_model("four-bar")
    lin_planar, lin_spatial = Linearization(planar), Linearization(as_spatial(planar))
    for start, kind in ((4.0, "oscillatory"), (1.0, "divergent")):
        linear_planar = lin_planar.at(q_start=[start])
        q_planar = dict(zip([q.name for q in lin_planar.q_all], lin_planar.full_operating_point(linear_planar)))
        linear_spatial = lin_spatial.at(q_start=[q_planar[q.name] for q in lin_spatial.q_all])
        assert linear_spatial.coordinates == linear_planar.coordinates == ["q_crank"]
        np.testing.assert_allclose(linear_spatial.q0, linear_planar.q0, rtol=1e-10)
        values = [_eigenvalues(linear) for linear in (linear_planar, linear_spatial)]
        np.testing.assert_allclose(values[1], values[0], rtol=1e-8, atol=1e-10)
        assert kind in [m.kind for m in modal_analysis(linear_spatial).modes]


def test_linearize_command_on_a_spatial_loop_model(tmp_path):
    from flexkane.cli import main

    out = tmp_path / "lin"
    assert main(["linearize", str(LOOPS / "axis_pendulum.toml"), "--out", str(out), "--quiet"]) == 0
    data = np.load(out / "linear_model.npz")
    assert list(data["state_names"]) == ["rx_pivot", "u_pivot_wx"]
    rows = (out / "modes.csv").read_text().splitlines()
    assert len(rows) == 2 and rows[1].split(",")[1] == "oscillatory"
    assert (out / "linear_model.mat").exists()


# ---------------------------------------------------------------- RSSR four-bar (closed form)
A, B, C = 0.1, 0.4, 0.25                 # crank, coupler, rocker lengths of rssr.toml [m]
PIVOT = np.array([0.2, 0.1, 0.2])        # rocker pivot [m]
M1, M2, M3, G = 0.3, 0.8, 0.5, 9.81


def _rocker(theta: float, phi: float) -> float:
    """The rocker angle closing the loop at crank angle theta, by Newton's method from phi."""
    def gap(p):
        tip = PIVOT + C * np.array([0.0, np.cos(p), np.sin(p)])
        return np.sum((tip - A * np.array([np.cos(theta), np.sin(theta), 0.0])) ** 2) - B ** 2
    for _ in range(60):
        step = -gap(phi) / ((gap(phi + 1e-7) - gap(phi - 1e-7)) / 2e-7)
        phi += step
        if abs(step) < 1e-15:
            break
    return phi


def _potential(theta: float, phi: float) -> float:
    """Gravity's potential [J]: the crank stays at z = 0, the coupler's centre at half the rocker tip's
    height, the rocker's at half its length."""
    return G * (M2 * (PIVOT[2] + C * np.sin(phi)) / 2 + M3 * (PIVOT[2] + C / 2 * np.sin(phi)))


def _rssr_energy_frequency(theta_guess: float, phi_guess: float, extreme) -> tuple[float, float]:
    """omega^2 = V''(theta) / m(theta) at the equilibrium (where the rocker turns back, phi' = 0), m the
    generalized mass 2 T at unit crank speed and no coupler spin."""
    def slope(theta):
        return (_rocker(theta + 1e-6, phi_guess) - _rocker(theta - 1e-6, phi_guess)) / 2e-6
    thetas = np.linspace(theta_guess - 0.3, theta_guess + 0.3, 61)
    phis = [_rocker(t, phi_guess) for t in thetas]
    k = int(extreme(phis))
    theta = brentq(slope, thetas[k - 1], thetas[k + 1], xtol=1e-15)
    phi = _rocker(theta, phi_guess)

    def second(h):
        return (_potential(theta + h, _rocker(theta + h, phi)) - 2 * _potential(theta, phi)
                + _potential(theta - h, _rocker(theta - h, phi))) / h ** 2
    stiffness = (4 * second(5e-4) - second(1e-3)) / 3          # Richardson
    rate = (_rocker(theta + 1e-6, phi) - _rocker(theta - 1e-6, phi)) / 2e-6
    crank_tip = A * np.array([np.cos(theta), np.sin(theta), 0.0])
    rocker_tip = PIVOT + C * np.array([0.0, np.cos(phi), np.sin(phi)])
    v_a = A * np.array([-np.sin(theta), np.cos(theta), 0.0])
    v_b = C * np.array([0.0, -np.sin(phi), np.cos(phi)]) * rate
    axis = (rocker_tip - crank_tip) / B
    omega = np.cross(axis, (v_b - v_a) / B)
    mass = (M1 * A ** 2 / 3 + M2 * np.sum(((v_a + v_b) / 2) ** 2) + M2 * B ** 2 / 12 * np.sum(omega ** 2)
            + M3 * C ** 2 / 3 * rate ** 2)
    return theta, stiffness / mass


@pytest.mark.slow
def test_rssr_four_bar_linear_frequencies_equal_the_energy_method():
    """Hanging (the rocker at its lowest, stable) and upright (at its highest, divergent); the
    coupler's idle spin about its own axis is the rigid-body mode."""
    model = load_model(LOOPS / "rssr.toml")
    lin = Linearization(model)
    cases = [({"q_crank": 3.98, "q_rocker": -1.05}, -1.05, np.argmin, "oscillatory"),
             ({}, 0.29, np.argmax, "divergent")]
    for initial, phi_guess, extreme, kind in cases:
        start = lin.q_initial.copy()
        for name, value in initial.items():
            start[[q.name for q in lin.q_all].index(name)] = value
        linear = lin.at(q_start=start)
        assert linear.coordinates == ["q_crank", "rx_coupler"]
        assert set(linear.dropped) == {"q_rocker", "ry_coupler", "rz_coupler"}
        theta, omega_squared = _rssr_energy_frequency(linear.q0[0], phi_guess, extreme)
        assert linear.q0[0] == pytest.approx(theta, abs=1e-8)
        modes = modal_analysis(linear).modes
        assert sorted(m.kind for m in modes).count("rigid") == 1
        mode = [m for m in modes if m.kind == kind][0]
        value = mode.omega ** 2 if kind == "oscillatory" else -mode.eigenvalue.real ** 2
        assert value == pytest.approx(omega_squared, rel=1e-7)


def _turn(axis, angle: float) -> np.ndarray:
    a = np.asarray(axis, dtype=float) / np.linalg.norm(axis)
    K = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return np.eye(3) + np.sin(angle) * K + (1 - np.cos(angle)) * K @ K


@pytest.mark.slow
def test_welded_pair_swings_as_one_physical_pendulum():
    """All six speeds of the free joint dependent: the pair is one rigid body on the horizontal hinge
    axis (1, 1, 0), omega^2 = m g rho / I_n with the composite inertia (block turned by the weld's
    orientation, its point W at the arm's)."""
    model = load_model(LOOPS / "welded_pair.toml")
    turn = _turn([0, 1, 0], 0.4)
    m1, m2 = 1.0, 0.5
    c1 = np.array([0.0, 0.0, -0.3])
    c2 = np.array([0.1, 0.05, -0.2]) - [0.0, 0.0, 0.3] - turn @ np.array([-0.05, 0.02, 0.1])
    inertia2 = turn @ np.array([[0.004, 0.0005, 0.0], [0.0005, 0.006, 0.0], [0.0, 0.0, 0.005]]) @ turn.T

    def about_pivot(inertia, m, c):
        return inertia + m * (c @ c * np.eye(3) - np.outer(c, c))
    total = about_pivot(np.diag([0.02, 0.03, 0.04]), m1, c1) + about_pivot(inertia2, m2, c2)
    n = np.array([1.0, 1.0, 0.0]) / np.sqrt(2)
    centre = (m1 * c1 + m2 * c2) / (m1 + m2)
    rho = np.linalg.norm(centre - (centre @ n) * n)
    linear = Linearization(model).at()
    assert linear.coordinates == ["q_hinge"]
    assert set(linear.dropped) == {"q_float_x", "q_float_y", "q_float_z", "rx_float", "ry_float", "rz_float"}
    modes = modal_analysis(linear).modes
    assert [m.kind for m in modes] == ["oscillatory"]
    assert modes[0].omega == pytest.approx(np.sqrt((m1 + m2) * G * rho / (n @ total @ n)), rel=1e-9)


@pytest.mark.slow
def test_free_spin_of_a_chain_with_loops_is_refused():
    with pytest.raises(flexkane.ModelError, match="without closed loops"):
        Linearization(load_model(LOOPS / "axis_pendulum.toml"), about="spin", spin=1.0, hub="pivot",
                      spin_axis=(1, 0, 0))
