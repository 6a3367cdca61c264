"""Linear models for control design: named inputs, outputs and states, python-control, closed loops.

Physics oracles: a P controller on a free hub is a torsional spring, so the linear model of the
sprung hub is A - B K of the free one; an LQR designed on the linear model and simulated on the
nonlinear one makes its slowest closed-loop mode decay at the rate of the eigenvalue of A - B K.
"""

import numpy as np
import pytest
import scipy.io
from control_models import KP, hub_beam

import flexkane
from flexkane.cli import main
from flexkane.extras import MissingExtraError
from flexkane.analysis import linearize, load_control

control = pytest.importorskip("control")


@pytest.fixture(scope="module")
def free_hub():
    return linearize(hub_beam(spring=False))


def test_closed_loop_of_a_p_controller_is_a_minus_b_k_of_the_open_loop(free_hub):
    sprung = linearize(hub_beam(spring=True))
    assert free_hub.state_names == sprung.state_names and free_hub.input_names == ["input_effort_hub"]
    A, B = free_hub.state_space()
    gain = np.zeros((1, A.shape[0]))
    gain[0, free_hub.state_names.index("q_hub")] = KP
    A_spring, _ = sprung.state_space()
    np.testing.assert_allclose(A - B @ gain, A_spring, rtol=0, atol=1e-12 * np.abs(A_spring).max())
    by_frequency = lambda lam: lam[np.argsort(lam.imag)]  # noqa: E731 - undamped: real parts ~ 1e-15
    np.testing.assert_allclose(by_frequency(np.linalg.eigvals(A - B @ gain)),
                               by_frequency(np.linalg.eigvals(A_spring)), atol=1e-9)


def test_lqr_controlled_arm_decays_at_the_rate_of_the_closed_loop_eigenvalue(free_hub):
    linear = free_hub
    A, B = linear.state_space()
    C, _ = linear.output_matrices()
    n = linear.n
    Q = np.diag([100.0] + [0.0] * (n - 1) + [1.0] + [0.0] * (n - 1))
    K, _, _ = control.lqr(linear.to_control(), Q, np.eye(1))
    lam, V = np.linalg.eig(A - B @ K)
    k = max((i for i in range(lam.size) if lam[i].imag > 0), key=lambda i: lam[i].real)   # slowest pair
    v = V[:, k] / np.abs(V[:n, k]).max() * 1e-3
    x0 = v.real                              # excites that pair only: x(t) = Re(v exp(lambda t))
    t_end = 3.0 / -lam[k].real
    compiled = flexkane.compile_model(flexkane.derive(hub_beam(spring=False)))
    run = flexkane.simulate(compiled, controller=lambda t, y: -K @ y, y0=x0, t_end=t_end, dt_out=t_end / 150,
                            rtol=1e-10, atol=1e-14)
    predicted = np.array([(v * np.exp(lam[k] * t)).real for t in run.t])
    tip = linear.output_names.index("tip_link")
    np.testing.assert_allclose(run["tip_link"], predicted @ C[tip] + linear.y0[tip], rtol=0,
                               atol=1e-4 * np.abs(predicted @ C[tip]).max())      # O(amplitude) nonlinearity
    modal = np.linalg.inv(V)[k] @ run.state.T                   # the mode's coordinate: 1/2 exp(lambda t)
    rate = np.polyfit(run.t, np.log(np.abs(modal)), 1)[0]
    assert rate == pytest.approx(lam[k].real, rel=1e-3)
    assert np.abs(modal[-1] / modal[0]) == pytest.approx(np.exp(-3.0), rel=1e-3)


def test_state_space_for_python_control_has_the_names_and_matrices(free_hub, tmp_path):
    system = free_hub.to_control()
    A, B = free_hub.state_space()
    C, D = free_hub.output_matrices()
    np.testing.assert_array_equal(system.A, A)
    np.testing.assert_array_equal(system.B, B)
    np.testing.assert_array_equal(system.C, C)
    np.testing.assert_array_equal(system.D, D)
    assert system.state_labels == free_hub.state_names
    assert system.input_labels == ["input_effort_hub"]
    assert system.output_labels == free_hub.output_names and "tip_link" in system.output_labels
    assert "energy" not in system.output_labels
    free_hub.save_control(tmp_path / "s.npz")
    again = load_control(tmp_path / "s.npz")
    np.testing.assert_array_equal(again.A, A)
    assert again.output_labels == system.output_labels and again.isctime()
    free_hub.save_mat(tmp_path / "s.mat")
    struct = scipy.io.loadmat(tmp_path / "s.mat")["statespace"][0, 0]
    np.testing.assert_array_equal(struct["B"], B)
    np.testing.assert_array_equal(struct["C"], C)
    assert [str(c[0][0]) for c in struct["InputName"]] == ["input_effort_hub"]


def test_command_line_exports_the_state_space_for_python_control(tmp_path, capsys):
    out = tmp_path / "lin"
    assert main(["linearize", "flexible-arm", "--n-modes", "2", "--export", "control", "--out", str(out)]) == 0
    assert "wrote 5 files" in capsys.readouterr().out
    system = load_control(out / "statespace.npz")
    assert system.input_labels == ["input_effort_shoulder"] and "tip_link" in system.output_labels
    assert main(["linearize", "flexible-arm", "--export", "simulink", "--out", str(tmp_path / "x")]) == 2
    assert "--export" in capsys.readouterr().err


def test_missing_python_control_names_the_extra(free_hub, monkeypatch):
    import sys

    monkeypatch.setitem(sys.modules, "control", None)
    with pytest.raises(MissingExtraError, match=r"flexkane\[control\]"):
        free_hub.to_control()


def test_output_with_accelerations_gets_its_direct_feedthrough_d():
    """The effort of a driven turntable depends on the accelerations a hinge actuator causes: C and D of
    that output agree with central differences of the compiled outputs in the state and the input."""
    from flexkane import Model
    from flexkane.kane.inputs import with_control_inputs
    from flexkane.model.parts import Beam, Driver, Joint, RigidBody

    model = Model(name="turntable", parameters={"J": 0.2, "m": 1.0, "L": 0.7, "EI": 5.0, "rho": 0.4})
    model.bodies["table"] = RigidBody(name="table", mass="m", inertia="J", points={"hinge": (0.1, 0.05)})
    model.beams["arm"] = Beam(name="arm", L="L", EI="EI", rho="rho", n_modes=2)
    model.joints["table"] = Joint(name="table", type="revolute", parent="ground", child="table",
                                  driver=Driver(speed="0"))
    model.joints["elbow"] = Joint(name="elbow", type="revolute", parent="table", parent_point="hinge",
                                  child="arm", stiffness=3.0, rest=0.4)
    model.validate()
    linear = linearize(model)
    assert linear.input_names == ["input_effort_elbow"] and "effort_table" in linear.output_names
    C, D = linear.output_matrices()
    row = linear.output_names.index("effort_table")
    assert abs(D[row, 0]) > 1e-3
    compiled = flexkane.compile_model(flexkane.derive(with_control_inputs(model)))
    module = compiled.module
    p0 = compiled.derivation.numbers(compiled.derivation.model, ("p",))["p"]
    names = list(module.STATE_NAMES)
    x0 = np.zeros(len(names))
    for name, value in zip(linear.coordinates, linear.q0):
        x0[names.index(name)] = value
    k_in = list(module.CONSTANT_NAMES).index("input_effort_elbow")
    k_out = list(module.OUTPUT_NAMES).index("effort_table")

    def effort(x, r):
        p = np.array(p0, dtype=float)
        p[k_in] = r
        return module.outputs(np.zeros(1), x[None, :], p)[0, k_out]

    h = 1e-6
    D_fd = (effort(x0, h) - effort(x0, -h)) / (2 * h)
    assert D[row, 0] == pytest.approx(D_fd, rel=1e-6)
    for j, name in enumerate(linear.state_names):
        e = np.zeros(len(names))
        e[names.index(name)] = h
        C_fd = (effort(x0 + e, 0.0) - effort(x0 - e, 0.0)) / (2 * h)
        assert C[row, j] == pytest.approx(C_fd, rel=1e-5, abs=1e-6 * np.abs(C[row]).max())
