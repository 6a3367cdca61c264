"""Linearization of spatial (dimensions = 3) rigid chains: rotation coordinates for Euler parameters.

Physics is the oracle: a torque-free rigid body spinning about each principal axis (the intermediate
axis unstable at the classical rate, the others oscillating at the classical frequency), a spherical
pendulum hanging at rest (two pairs sqrt(m g l / I_pivot)), a heavy symmetric top spinning upright
(stable above the Maxwell-Klein speed I_3^2 Omega^2 = 4 I_1 m g l, unstable below, with the
precession and nutation frequencies of the classical theory), and a planar chain run through the
spatial engine (the planar engine's eigenvalues).
"""

from __future__ import annotations

import numpy as np
import pytest

from flexkane.errors import ModelError
from flexkane.analysis import Linearization, NoEquilibriumError, modal_analysis
from flexkane.analysis.rotation_reduction import RotationReduction, euler_matrix, turn
from flexkane.model import as_spatial, loads_model

G = 9.81
I1, I2, I3 = 1.0, 2.0, 2.5          # principal moments of the torque-free body [kg m^2]
OMEGA = 2.0                         # its spin rate [rad/s]

TORQUE_FREE = f"""
name = "torque-free"
dimensions = 3
[bodies.box]
mass = 2.0
inertia = [{I1}, {I2}, {I3}]
[joints.pivot]
type = "spherical"
parent = "ground"
parent_position = [0, 0, 0]
child = "box"
"""

PEND_M, PEND_L, PEND_IC = 2.0, 0.5, 0.01      # mass [kg], pivot to mass centre [m], I about the centre [kg m^2]
PENDULUM = f"""
name = "spherical-pendulum"
dimensions = 3
[bodies.bob]
mass = {PEND_M}
inertia = [{PEND_IC}, {PEND_IC}, 0.004]
points = {{ top = [0, 0, {PEND_L}] }}
[joints.socket]
type = "spherical"
parent = "ground"
parent_position = [0, 0, 0]
child = "bob"
child_point = "top"
[gravity]
g = {G}
direction = [0, 0, -1]
[initial]
q_socket = {{ axis = [1, 1, 0], angle = 0.4 }}
"""

TOP_M, TOP_L, TOP_IC, TOP_I3 = 0.8, 0.07, 0.012, 0.02   # kg, m (pivot to centre), kg m^2, kg m^2
TOP = f"""
name = "heavy-top"
dimensions = 3
[bodies.top]
mass = {TOP_M}
inertia = [{TOP_IC}, {TOP_IC}, {TOP_I3}]
points = {{ tip = [0, 0, {-TOP_L}] }}
[joints.pivot]
type = "spherical"
parent = "ground"
parent_position = [0, 0, 0]
child = "top"
child_point = "tip"
[gravity]
g = {G}
direction = [0, 0, -1]
"""

PLANAR = """
name = "planar-pendulum-chain"
[bodies.upper]
mass = 1.5
inertia = 0.05
points = { top = [-0.3, 0.0], bottom = [0.3, 0.02] }
[bodies.lower]
mass = 0.8
inertia = 0.02
points = { top = [-0.2, 0.0], end = [0.2, 0.0] }
[bodies.slider]
mass = 0.3
inertia = 0.001
[joints.shoulder]
type = "revolute"
parent = "ground"
child = "upper"
parent_position = [0.0, 0.0]
child_point = "top"
angle = -1.2
stiffness = 3.0
damping = 0.2
[joints.elbow]
type = "revolute"
parent = "upper"
child = "lower"
parent_point = "bottom"
child_point = "top"
stiffness = 2.0
rest = 0.3
damping = 0.1
[joints.rail]
type = "prismatic"
parent = "lower"
child = "slider"
parent_point = "end"
axis = 0.0
stiffness = 40.0
damping = 0.5
[gravity]
g = 9.81
direction = [0, -1]
"""


@pytest.fixture(scope="module")
def torque_free():
    model = loads_model(TORQUE_FREE)
    return {axis: Linearization(model, about="spin", spin=OMEGA, spin_axis=np.eye(3)[axis]) for axis in range(3)}


@pytest.fixture(scope="module")
def top():
    return Linearization(loads_model(TOP), about="spin", spin=1.0, spin_axis=(0, 0, 1))


def _eigenvalues(linear) -> np.ndarray:
    return np.linalg.eigvals(linear.state_space()[0])


def test_rotation_map_is_the_tangent_of_the_turn_and_its_pseudo_inverse():
    e = turn(np.array([1.0, 0.0, 0.0, 0.0]), np.array([0.3, -0.7, 1.1]))
    E = euler_matrix(e)
    np.testing.assert_allclose(E.T @ E, np.eye(3), atol=1e-15)
    np.testing.assert_allclose(E.T @ e, np.zeros(3), atol=1e-15)
    h = 1e-6
    for k in range(3):      # de/dtheta_k of the exact turn = 1/2 E(e) e_k
        d = (turn(e, h * np.eye(3)[k]) - turn(e, -h * np.eye(3)[k])) / (2 * h)
        np.testing.assert_allclose(d, 0.5 * E[:, k], atol=1e-9)


def test_reduced_states_are_named_after_the_joint(torque_free):
    linear = torque_free[1].at()
    assert linear.coordinates == ["rx_pivot", "ry_pivot", "rz_pivot"]
    assert linear.speeds == ["u_pivot_wx", "u_pivot_wy", "u_pivot_wz"]
    assert linear.state_names[:3] == ["rx_pivot", "ry_pivot", "rz_pivot"]
    np.testing.assert_array_equal(linear.q0, np.zeros(3))


def test_spinning_body_kinematics_in_rotation_coordinates(torque_free):
    """dtheta' = dtheta x w0 + dw about a steady spin w0 (constant coefficients though e turns)."""
    linear = torque_free[1].at()
    w0 = OMEGA * np.eye(3)[1]
    cross = np.array([[0, -w0[2], w0[1]], [w0[2], 0, -w0[0]], [-w0[1], w0[0], 0]])
    np.testing.assert_allclose(linear.V, -cross, atol=1e-14)
    np.testing.assert_allclose(linear.W, np.eye(3), atol=1e-14)


def test_torque_free_body_intermediate_axis_is_unstable(torque_free):
    linear = torque_free[1].at()
    values = _eigenvalues(linear)
    expected = OMEGA * np.sqrt((I2 - I1) * (I3 - I2) / (I1 * I3))
    assert np.max(values.real) == pytest.approx(expected, rel=1e-8)
    growing = values[np.argmax(values.real)]
    assert abs(growing.imag) <= 1e-12
    assert not modal_analysis(linear).stable


@pytest.mark.parametrize("axis", [0, 2], ids=["minor", "major"])
def test_torque_free_body_spin_about_the_extreme_axes_is_stable(torque_free, axis):
    linear = torque_free[axis].at()
    values = _eigenvalues(linear)
    I = np.array([I1, I2, I3])
    a, b = [k for k in range(3) if k != axis]
    classical = OMEGA * np.sqrt((I[axis] - I[a]) * (I[axis] - I[b]) / (I[a] * I[b]))
    assert np.max(np.abs(values.real)) <= 1e-12
    # Euler's equations: 0, +-i classical; the attitude seen from the spinning frame: 0, +-i Omega
    expected = np.sort(np.array([0.0, 0.0, classical, classical, OMEGA, OMEGA]))
    np.testing.assert_allclose(np.sort(np.abs(values.imag)), expected, rtol=1e-8, atol=1e-12)


def test_spherical_pendulum_hanging_at_rest():
    """Searched from a tilted start in rotation coordinates; two pairs sqrt(m g l / I_pivot)."""
    lin = Linearization(loads_model(PENDULUM), about="equilibrium")
    linear = lin.at()
    q = lin.full_operating_point(linear)
    e0, e1, e2, e3 = q[:4]        # the bob hangs: its z axis (pivot above the mass centre) points up
    z_axis = np.array([2 * (e1 * e3 + e0 * e2), 2 * (e2 * e3 - e0 * e1), e0 ** 2 - e1 ** 2 - e2 ** 2 + e3 ** 2])
    assert z_axis[2] == pytest.approx(1.0, abs=1e-10)
    frequency = np.sqrt(PEND_M * G * PEND_L / (PEND_IC + PEND_M * PEND_L ** 2))
    modes = modal_analysis(linear)
    oscillating = sorted(m.omega for m in modes.modes if m.kind == "oscillatory")
    np.testing.assert_allclose(oscillating, [frequency, frequency], rtol=1e-10)
    assert len(modes.rigid) == 1       # the turn about the vertical


def test_heavy_top_is_stable_above_the_critical_speed_and_unstable_below(top):
    I1_pivot = TOP_IC + TOP_M * TOP_L ** 2
    critical = np.sqrt(4 * I1_pivot * TOP_M * G * TOP_L) / TOP_I3
    for factor in (0.5, 0.95):
        values = _eigenvalues(top.at(spin=factor * critical))
        assert np.max(values.real) > 1e-3 * critical
    for factor in (1.05, 3.0):
        spin = factor * critical
        values = _eigenvalues(top.at(spin=spin))
        assert np.max(np.abs(values.real)) <= 1e-10 * spin
        # nutation and precession in space: I_1 w^2 - I_3 Omega w + m g l = 0; seen from the top, w - Omega
        root = np.sqrt((TOP_I3 * spin) ** 2 - 4 * I1_pivot * TOP_M * G * TOP_L)
        space = np.array([TOP_I3 * spin + root, TOP_I3 * spin - root]) / (2 * I1_pivot)
        expected = np.sort(np.abs(np.concatenate([space - spin, space - spin, [0.0, 0.0]])))
        np.testing.assert_allclose(np.sort(np.abs(values.imag)), expected, rtol=1e-8, atol=1e-10)


def test_spin_about_an_axis_that_turns_gravity_is_not_a_steady_spin():
    """A hanging pendulum spun about a horizontal body axis: balanced at t0, but gravity's moment
    changes as it turns, so the linear model would be periodic: refused."""
    text = PENDULUM.split("[initial]")[0]
    lin = Linearization(loads_model(text), about="spin", spin=3.0, spin_axis=(1, 0, 0))
    with pytest.raises(NoEquilibriumError, match="no steady spin of joint socket"):
        lin.at()


def test_planar_chain_through_the_spatial_engine_has_the_planar_eigenvalues():
    planar = loads_model(PLANAR)
    values = [np.sort_complex(_eigenvalues(Linearization(m, about="equilibrium").at()))
              for m in (planar, as_spatial(planar))]
    assert values[0].size == 6
    np.testing.assert_allclose(values[1], values[0], rtol=1e-8, atol=1e-10)


def test_spin_axis_refusals():
    with pytest.raises(ModelError, match="spin-axis"):
        Linearization(loads_model(PLANAR), about="spin", spin=1.0, spin_axis=(0, 0, 1))
    with pytest.raises(ModelError, match="spin-axis"):
        Linearization(loads_model(TORQUE_FREE), about="spin", spin=1.0, spin_axis=(0, 0, 0))
    with pytest.raises(ModelError, match="spin-axis"):
        Linearization(loads_model(TORQUE_FREE), about="equilibrium", spin_axis=(0, 0, 1))
    with pytest.raises(ModelError, match="--hub"):
        Linearization(loads_model(TORQUE_FREE), about="spin", spin=1.0, hub="box", spin_axis=(0, 0, 1))


def test_rotation_reduction_of_a_planar_chain_is_none():
    from flexkane.kane import derive

    eom = derive(loads_model(PLANAR))
    assert RotationReduction.of(eom.chain.coordinates, [q.name for q in eom.q]) is None


FREE_BODY = TORQUE_FREE.replace('name = "torque-free"', 'name = "free-body"').replace(
    'type = "spherical"', 'type = "free"').replace("[joints.pivot]", "[joints.float]") + \
    "[initial]\nq_float_x = 0.3\nq_float_z = -0.2\n"


def test_free_body_spinning_about_the_intermediate_axis_translations_in_the_turning_frame():
    """A free joint spinning freely: translations measured along the spinning frame (sx, sy, sz),
    dxi' = dv - w0 x dxi, and the same instability as on a spherical joint."""
    lin = Linearization(loads_model(FREE_BODY), about="spin", spin=OMEGA, spin_axis=(0, 1, 0))
    linear = lin.at()
    assert linear.coordinates == ["sx_float", "sy_float", "sz_float", "rx_float", "ry_float", "rz_float"]
    w0 = np.array([0.0, OMEGA, 0.0])
    cross = np.array([[0, -w0[2], w0[1]], [w0[2], 0, -w0[0]], [-w0[1], w0[0], 0]])
    np.testing.assert_allclose(linear.V[:3, :3], -cross, atol=1e-14)
    np.testing.assert_allclose(linear.W, np.eye(6), atol=1e-14)
    expected = OMEGA * np.sqrt((I2 - I1) * (I3 - I2) / (I1 * I3))
    assert np.max(_eigenvalues(linear).real) == pytest.approx(expected, rel=1e-8)
    # the operating point keeps the body where it is; a shift along the body's x moves it there
    moved = lin.configuration(linear, np.array([0.1, 0, 0, 0, 0, 0]))
    assert [moved[s] for s in lin.q_all[:3]] == pytest.approx([0.4, 0.0, -0.2], abs=1e-15)


def test_linearize_and_campbell_commands_on_a_spatial_model(tmp_path):
    from flexkane.cli import main

    path = tmp_path / "torque-free.toml"
    path.write_text(TORQUE_FREE)
    out = tmp_path / "lin"
    assert main(["linearize", str(path), "--about", "spin", "--spin", str(OMEGA), "--spin-axis", "0,1,0",
                 "--out", str(out), "--quiet", "--export", "control"]) == 0
    data = np.load(out / "linear_model.npz")
    assert list(data["state_names"][:3]) == ["rx_pivot", "ry_pivot", "rz_pivot"]
    assert (out / "modes.csv").exists() and not (out / "mode_shapes.png").exists()
    assert main(["campbell", str(path), "--spin", "0:4:3", "--spin-axis", "1,0,0", "--out", str(tmp_path / "c"),
                 "--quiet"]) == 0
    lines = (tmp_path / "c" / "campbell.csv").read_text().splitlines()
    assert len(lines) == 4
    last = [float(v) for v in lines[-1].split(",")]      # Omega = 4 about the minor axis
    assert last[1] == pytest.approx(4.0 * np.sqrt((I2 - I1) * (I3 - I1) / (I2 * I3)), rel=1e-8)
    with pytest.raises(SystemExit) as exit_info:
        main(["linearize", str(path), "--about", "spin", "--spin", "1", "--spin-axis", "0,1", "--out",
              str(tmp_path / "bad")])
    assert exit_info.value.code == 2
    assert main(["linearize", str(path), "--about", "spin", "--spin", "1", "--out", str(tmp_path / "bad2")]) == 2


HUB_ARM = """
name = "hub-arm"
[bodies.hub]
mass = 5.0
inertia = 0.5
points = { tip = [0.2, 0.0] }
[bodies.arm]
mass = 1.0
inertia = 0.03
points = { root = [-0.3, 0.0] }
[joints.spin]
type = "revolute"
parent = "ground"
child = "hub"
parent_position = [0, 0]
torque = 1.0
[joints.hinge]
type = "revolute"
parent = "hub"
child = "arm"
parent_point = "tip"
child_point = "root"
stiffness = 10.0
damping = 0.1
"""


def test_planar_hub_through_the_spatial_engine_has_the_planar_campbell_diagram():
    """A driven revolute hub (the planar steady spin) in 3D: same frequencies and growth rates."""
    from flexkane.analysis import campbell_diagram

    planar = loads_model(HUB_ARM)
    diagrams = [campbell_diagram(m, [0.0, 2.0, 4.0]) for m in (planar, as_spatial(planar))]
    assert diagrams[1].hub == "spin"
    np.testing.assert_allclose(diagrams[1].frequencies, diagrams[0].frequencies, rtol=1e-8)
    np.testing.assert_allclose(diagrams[1].growth_rates, diagrams[0].growth_rates, rtol=1e-8)
    assert diagrams[0].frequencies[2, 0] > diagrams[0].frequencies[0, 0]     # centrifugal stiffening


def _double_pendulum(spatial: bool) -> str:
    """Two bodies hanging from each other: on revolute joints in the x-y plane, or on spherical joints
    along z with the same moment of inertia about both horizontal axes."""
    bodies = {"upper": (1.2, 0.04, 0.35, -0.25), "lower": (0.7, 0.02, 0.2, -0.3)}   # m, J, top, bottom
    lines = ['name = "double"'] + (["dimensions = 3"] if spatial else [])
    for name, (m, J, top, bottom) in bodies.items():
        point = (lambda h: f"[0, 0, {h}]") if spatial else (lambda h: f"[0, {h}]")
        inertia = f"[{J}, {J}, 0.005]" if spatial else f"{J}"
        lines += [f"[bodies.{name}]", f"mass = {m}", f"inertia = {inertia}",
                  f"points = {{ top = {point(top)}, bottom = {point(bottom)} }}"]
    kind = "spherical" if spatial else "revolute"
    lines += ["[joints.j1]", f'type = "{kind}"', 'parent = "ground"', 'child = "upper"',
              f"parent_position = {'[0, 0, 0]' if spatial else '[0, 0]'}", 'child_point = "top"',
              "[joints.j2]", f'type = "{kind}"', 'parent = "upper"', 'child = "lower"', 'parent_point = "bottom"',
              'child_point = "top"', "[gravity]", "g = 9.81", f"direction = {'[0, 0, -1]' if spatial else '[0, -1]'}"]
    return "\n".join(lines) + "\n"


def test_double_spherical_pendulum_swings_in_both_planes_as_the_planar_double_pendulum():
    """Two spherical joints (two rotation blocks): each planar frequency twice, the turns about the
    vertical rigid."""
    planar = modal_analysis(Linearization(loads_model(_double_pendulum(False)), about="equilibrium").at())
    spatial = modal_analysis(Linearization(loads_model(_double_pendulum(True)), about="rest").at())
    flat = sorted(m.omega for m in planar.modes if m.kind == "oscillatory")
    assert len(flat) == 2
    swings = sorted(m.omega for m in spatial.modes if m.kind == "oscillatory")
    np.testing.assert_allclose(swings, sorted(flat + flat), rtol=1e-10)
    assert len(spatial.rigid) == 2


DOUBLE_SKEW = """
name = "skew-double"
dimensions = 3
[bodies.A]
mass = 2.0
inertia = [[0.1, 0.01, 0.0], [0.01, 0.2, 0.02], [0.0, 0.02, 0.15]]
points = { top = [0.0, 0.0, 0.5], bottom = [0.1, 0.0, -0.5] }
[bodies.B]
mass = 1.5
inertia = [[0.05, 0.0, 0.01], [0.0, 0.07, 0.0], [0.01, 0.0, 0.03]]
points = { top = [0.0, 0.05, 0.4] }
[joints.j1]
type = "spherical"
parent = "ground"
parent_position = [0, 0, 0]
child = "A"
child_point = "top"
[joints.j2]
type = "spherical"
parent = "A"
parent_point = "bottom"
child = "B"
child_point = "top"
[gravity]
g = 9.81
direction = [0, 0, -1]
[initial]
q_j1 = { sequence = "xy", angles = [0.3, -0.2] }
q_j2 = { axis = [1, 1, 1], angle = 0.4 }
"""


@pytest.fixture(scope="module")
def skew_double():
    lin = Linearization(loads_model(DOUBLE_SKEW), about="equilibrium")
    return lin, lin.at()


def test_tilted_double_spherical_pendulum_settles_hanging(skew_double):
    """Off-axis points and full inertia tensors, searched from a tilted start: a stable equilibrium
    (symmetric, positive semi-definite K; two neutral turns about the vertical)."""
    lin, linear = skew_double
    assert linear.residual <= 1e-9 * 9.81
    assert np.max(np.abs(linear.K - linear.K.T)) <= 1e-9 * np.abs(linear.K).max()     # conservative
    assert np.min(np.linalg.eigvalsh(0.5 * (linear.K + linear.K.T))) > -1e-9 * np.abs(linear.K).max()  # hanging
    assert modal_analysis(linear).stable


@pytest.mark.slow
def test_reduced_state_matrix_matches_finite_differences_of_the_compiled_rhs(skew_double):
    """A equals central differences of the compiled nonlinear rhs in (rotation coordinates, speeds)."""
    import flexkane

    lin, linear = skew_double
    A, _ = linear.state_space()
    eom = lin.eom
    compiled = flexkane.compile_model(eom)
    p = eom.parameter_vector(lin.model)
    q_ref = lin.full_operating_point(linear)
    T_plus = lin.reduction.tangent(q_ref)[1]
    n_q = q_ref.size
    assert np.max(np.abs(compiled.rhs(0.0, np.concatenate([q_ref, np.zeros(linear.n)]), p))) < 1e-9

    def reduced_rhs(x):
        q = lin.reduction.retract(q_ref, x[:linear.n])
        ydot = compiled.rhs(0.0, np.concatenate([q, x[linear.n:]]), p)
        return np.concatenate([T_plus @ ydot[:n_q], ydot[n_q:]])

    h = 1e-6
    A_fd = np.column_stack([(reduced_rhs(h * e) - reduced_rhs(-h * e)) / (2 * h) for e in np.eye(2 * linear.n)])
    np.testing.assert_allclose(A, A_fd, atol=1e-6 * np.abs(A).max())


def test_spatial_model_has_input_channels_of_its_load_components():
    """The spatial engine derives control inputs: a 3D load with a force and a torque vector gives six
    channels (components in the load's frame), whose columns of B are the partial velocities there;
    the load's own values stay in the equations (the push adds to m g, the torque tilts the
    pendulum)."""
    text = PENDULUM + """[loads.push]
body = "bob"
force = [0.0, 0.0, -1.0]
torque = [0.2, 0.0, 0.0]
frame = "ground"
"""
    linear = Linearization(loads_model(text), about="equilibrium").at()
    assert linear.input_names == [f"input_load_push_{k}" for k in ("fx", "fy", "fz", "tx", "ty", "tz")]
    assert linear.B.shape == (3, 6)
    np.testing.assert_allclose(linear.r0, [0.0, 0.0, -1.0, 0.2, 0.0, 0.0], rtol=0, atol=0)
    frequency = np.sqrt((PEND_M * G + 1.0) * PEND_L / (PEND_IC + PEND_M * PEND_L ** 2))   # the push adds to m g
    tilt = np.arcsin(0.2 / ((PEND_M * G + 1.0) * PEND_L))                                  # the torque tilts it
    swings = sorted(m.omega for m in modal_analysis(linear).modes if m.kind == "oscillatory")
    assert swings[0] == pytest.approx(frequency * np.sqrt(np.cos(tilt)), rel=1e-8)
    assert not any("control inputs of spatial models" in note for note in linear.notes)
    # a planar chain through the spatial engine has the planar engine's input matrix (a planar torque
    # is the spatial one about z)
    planar = Linearization(loads_model(PLANAR), about="equilibrium").at()
    planar_as_3d = Linearization(as_spatial(loads_model(PLANAR)), about="equilibrium").at()
    spatial_columns = {name.replace("_tz", "_torque"): k for k, name in enumerate(planar_as_3d.input_names)}
    columns = [spatial_columns[name] for name in planar.input_names]
    assert set(planar_as_3d.input_names) - {planar_as_3d.input_names[k] for k in columns} <= \
        {name for name in planar_as_3d.input_names if name.endswith(("_fz", "_tx", "_ty"))}
    np.testing.assert_allclose(planar_as_3d.B[:, columns], planar.B, rtol=1e-10, atol=1e-12)
