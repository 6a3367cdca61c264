"""The built-in model flexible-arm-lqr: LQR state feedback written in the model file.

Oracles: the gains in the file are python-control's ``lqr`` on flexkane's linear model of
flexible-arm with the weights its comment states; the closed loop's own linear model is A - B K of
the open loop's; on the nonlinear model the hub reaches the set-point and the tip deflection decays at
the rate of the slowest closed-loop eigenvalue.
"""

import importlib.util
from pathlib import Path

import numpy as np
import pytest

import flexkane
from flexkane.analysis import linearize

ROOT = Path(__file__).resolve().parents[1]
#: The design weights stated in the model file's comment.
Q_HUB_ANGLE, Q_HUB_RATE, Q_TIP, R_TORQUE = 400.0, 1.0, 1e4, 1.0


@pytest.fixture(scope="module")
def model():
    return flexkane.builtin_model("flexible-arm-lqr")


@pytest.fixture(scope="module")
def open_loop():
    """The plant: flexible-arm with its torque profile off, linearized about rest, on the three
    clamped-free modes the gains were designed on (no static correction shapes)."""
    plant = flexkane.builtin_model("flexible-arm").with_values({"T0": 0})
    plant.beams["link"].static_corrections = False
    return linearize(plant, about="rest")


@pytest.fixture(scope="module")
def closed_loop(model):
    return linearize(model, about="equilibrium")


def file_gains(model, names) -> np.ndarray:
    """The gain matrix K (1, n) of the model file, on the states in the order of ``names``."""
    return np.array([[float(model.parameters[f"k_{name}"]) for name in names]])


def test_gains_in_the_file_are_the_lqr_of_the_linear_model_with_the_stated_weights(model, open_loop):
    control = pytest.importorskip("control", reason="python-control (the control extra) is not installed")
    names = open_loop.state_names
    assert names == ["q_shoulder", "q_link_1", "q_link_2", "q_link_3",
                     "u_shoulder", "u_link_1", "u_link_2", "u_link_3"]
    A, B = open_loop.state_space()
    C, _ = open_loop.output_matrices()
    tip = C[open_loop.output_names.index("tip_link")]
    Q = np.diag([Q_HUB_ANGLE, 0, 0, 0, Q_HUB_RATE, 0, 0, 0]) + Q_TIP * np.outer(tip, tip)
    K, _, _ = control.lqr(A, B, Q, R_TORQUE * np.eye(1))
    np.testing.assert_allclose(file_gains(model, names), K, rtol=1e-6, atol=0)
    assert set(name for name in model.parameters if name.startswith("k_")) == {f"k_{n}" for n in names}


def test_gains_script_prints_the_gains_of_the_file(model, capsys):
    pytest.importorskip("control", reason="python-control (the control extra) is not installed")
    path = ROOT / "examples" / "flexible_arm_lqr_gains.py"
    spec = importlib.util.spec_from_file_location("flexible_arm_lqr_gains", path)
    script = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(script)
    assert script.main() == 0
    printed = dict(line.split(" = ") for line in capsys.readouterr().out.splitlines())
    assert list(printed) == [name for name in model.parameters if name.startswith("k_")]
    for name, text in printed.items():                 # printed to 10 significant digits, as in the file
        assert float(text) == pytest.approx(float(model.parameters[name]), rel=1e-9), name


def test_linear_model_of_the_closed_loop_is_a_minus_b_k_and_stable(model, open_loop, closed_loop):
    assert closed_loop.state_names == open_loop.state_names
    assert closed_loop.input_names == ["input_effort_shoulder"]
    # the equilibrium is the set-point: the hub at theta_ref, the link undeformed
    np.testing.assert_allclose(closed_loop.q0, [model.parameters["theta_ref"], 0, 0, 0], rtol=0, atol=1e-12)
    A, B = open_loop.state_space()
    A_closed, B_closed = closed_loop.state_space()
    expected = A - B @ file_gains(model, open_loop.state_names)
    np.testing.assert_allclose(A_closed, expected, rtol=0, atol=1e-10 * np.abs(expected).max())
    np.testing.assert_allclose(B_closed, B, rtol=0, atol=1e-10 * np.abs(B).max())
    assert np.linalg.eigvals(A_closed).real.max() < 0


def test_run_reaches_the_set_point_and_the_tip_decays_at_the_slowest_closed_loop_rate(model, closed_loop):
    lam = np.linalg.eigvals(closed_loop.state_space()[0])
    slowest = lam[np.argmax(lam.real)]              # a lightly damped pair: the third bending mode
    compiled = flexkane.compile_model(flexkane.derive(model))
    period = 2 * np.pi / abs(slowest.imag)
    run = flexkane.simulate(compiled, t_end=11.0, dt_out=period / 40, rtol=1e-10, atol=1e-14)
    assert not run.partial, run.solver["message"]
    late = run.t >= 5.0                             # the faster modes have decayed by exp(-12) and more
    theta_ref = float(model.parameters["theta_ref"])
    assert np.abs(run["q_shoulder"][late] - theta_ref).max() < 1e-4
    # envelope of the tip deflection: its largest value over each window of 10 periods of that pair
    window = 10 * period
    starts = np.arange(5.0, run.t[-1] - window, window)
    peaks = [np.abs(run["tip_link"][(run.t >= s) & (run.t < s + window)]).max() for s in starts]
    rate = np.polyfit(starts, np.log(peaks), 1)[0]
    assert rate == pytest.approx(slowest.real, rel=0.01)       # measured: 0.14 %
    assert peaks[-1] < 0.1 * peaks[0]
