"""Linear models of closed loops with controller states: x = (dq, du, dz).

flexible-arm-pid holds the flexible arm at theta_f against a disturbance torque tau_d with a PID
law whose integral of the tracking error is a controller state. Oracles: the equilibrium of the
integral state cancels the disturbance (z0 = tau_d / Ki, the hub at the set-point, the motor
torque equal to tau_d); A and B agree with central differences of the compiled nonlinear
right-hand side in every entry of (q, u, z) and in the disturbance; the slowest closed-loop mode
of the nonlinear simulation decays at the rate of its eigenvalue of A.
"""

import numpy as np
import pytest

import flexkane
from flexkane.analysis import linearize
from flexkane.numerics.constant_block import prepared_parameters


@pytest.fixture(scope="module")
def pid():
    model = flexkane.builtin_model("flexible-arm-pid")
    return model, linearize(model), flexkane.compile_model(flexkane.derive(model))


def _rhs(compiled, y, p):
    dy = np.empty(len(y))
    assert compiled.module.rhs(0.0, np.asarray(y, dtype=float), prepared_parameters(compiled.module, p), dy) == 0
    return dy


def _numbers(compiled):
    derivation = compiled.derivation
    return np.array(derivation.numbers(derivation.model, ("p",))["p"], dtype=float)


def test_integral_state_settles_where_it_cancels_the_disturbance(pid):
    model, linear, _ = pid
    par = model.parameters
    assert linear.state_names[-1] == "error_integral" and linear.controller_states == ["error_integral"]
    assert linear.z0 == pytest.approx([par["tau_d"] / par["Ki"]], rel=1e-12)
    assert linear.q0[linear.coordinates.index("q_shoulder")] == pytest.approx(par["theta_f"], rel=1e-12)
    motor = linear.y0[linear.output_names.index("controller_motor")]
    assert motor == pytest.approx(par["tau_d"], rel=1e-12)          # unsaturated: |tau_d| < tau_max
    assert linear.residual <= 1e-9


def test_state_matrix_matches_central_differences_in_q_u_and_z(pid):
    _, linear, compiled = pid
    assert list(compiled.module.STATE_NAMES) == linear.state_names
    A, B = linear.state_space()
    p = _numbers(compiled)
    x0 = np.concatenate([linear.q0, np.zeros(linear.n), linear.z0])
    np.testing.assert_allclose(_rhs(compiled, x0, p), 0.0, atol=1e-9)      # an equilibrium of the rhs
    A_fd = np.empty_like(A)
    for j in range(len(x0)):
        h = 1e-6 * max(1.0, abs(x0[j]))
        e = np.zeros(len(x0))
        e[j] = h
        A_fd[:, j] = (_rhs(compiled, x0 + e, p) - _rhs(compiled, x0 - e, p)) / (2 * h)
    scale = np.abs(A).max(axis=1, keepdims=True)
    assert np.all(np.abs(A_fd - A) <= 1e-6 * scale), np.max(np.abs(A_fd - A) / scale)
    z = linear.state_names.index("error_integral")
    assert A[:, z].any() and A[z].any()                       # the integral acts and is driven
    # the disturbance enters as -tau_d: its input column is minus the derivative in tau_d
    k = list(compiled.module.CONSTANT_NAMES).index("tau_d")
    h = 1e-6
    e = np.zeros(len(p))
    e[k] = h
    column = -(_rhs(compiled, x0, p + e) - _rhs(compiled, x0, p - e)) / (2 * h)
    b = B[:, linear.input_names.index("input_load_disturbance_torque")]
    np.testing.assert_allclose(b, column, rtol=0, atol=1e-6 * np.abs(b).max())


def test_slowest_closed_loop_mode_decays_at_the_rate_of_its_eigenvalue(pid):
    _, linear, compiled = pid
    A, _ = linear.state_space()
    lam, V = np.linalg.eig(A)
    real = np.flatnonzero(np.abs(lam.imag) < 1e-12)
    k = int(real[np.argmax(lam[real].real)])                   # the slowest real mode (the integral's)
    assert lam[k].real < 0 and np.all(lam.real < 0)
    v = V[:, k].real / np.abs(V[:linear.n, k].real).max() * 1e-3
    x_eq = np.concatenate([linear.q0, np.zeros(linear.n), linear.z0])
    t_end = 3.0 / -lam[k].real
    run = flexkane.simulate(compiled, y0=x_eq + v, t_end=t_end, dt_out=t_end / 150, rtol=1e-10, atol=1e-13)
    modal = np.linalg.inv(V)[k].real @ (run.state - x_eq).T         # the mode's coordinate: exp(lambda t)
    rate = np.polyfit(run.t, np.log(np.abs(modal)), 1)[0]
    assert rate == pytest.approx(lam[k].real, rel=1e-3)
    assert modal[-1] / modal[0] == pytest.approx(np.exp(-3.0), rel=1e-3)
    assert np.abs(run["controller_motor"]).max() < linear.y0[linear.output_names.index("controller_motor")] + 0.1


def test_python_control_model_of_the_closed_loop_has_the_controller_state(pid, tmp_path):
    control = pytest.importorskip("control")
    import scipy.io

    from flexkane.analysis import load_control

    _, linear, _ = pid
    system = linear.to_control()
    assert system.state_labels == linear.state_names and system.nstates == 2 * linear.n + 1
    assert "controller_motor" in system.output_labels
    A, B = linear.state_space()
    np.testing.assert_array_equal(system.A, A)
    np.testing.assert_allclose(np.sort_complex(control.poles(system)), np.sort_complex(np.linalg.eigvals(A)))
    with pytest.raises(ValueError, match="controller states"):
        linear.second_order()
    linear.save_control(tmp_path / "s.npz")
    again = load_control(tmp_path / "s.npz")
    assert again.state_labels == linear.state_names
    np.testing.assert_array_equal(again.B, B)
    with np.load(tmp_path / "s.npz") as data:
        np.testing.assert_array_equal(data["x0"], np.concatenate([linear.q0, np.zeros(linear.n), linear.z0]))
    linear.save_mat(tmp_path / "s.mat")
    mat = scipy.io.loadmat(tmp_path / "s.mat")
    assert [str(c[0][0]) for c in mat["statespace"][0, 0]["StateName"]][-1] == "error_integral"
    np.testing.assert_array_equal(mat["K_z"], linear.K_z)


def test_symbolic_matrices_name_the_gains_of_the_pid(pid):
    """The Jacobians of the forcing and of z' in z, symbolic: the integral gain Ki on the hub's speed
    equation and z' = theta_f - q_shoulder (unsaturated: Max and Min differentiate to the linear law)."""
    import sympy as sp

    _, linear, _ = pid
    lin = linear.linearization
    sym = lin.symbolic_matrices()
    assert sym["Z_z"] == sp.zeros(1, 1) and sym["Z_u"] == sp.zeros(1, linear.n) and sym["Z_r"] == sp.zeros(1, 2)
    assert sym["Z_q"][0, [q.name for q in lin.q_all].index("q_shoulder")] == -1
    values = dict(zip(lin.parameters, lin.p)) | dict(zip(lin.q_all, linear.q0)) | {lin.z[0]: linear.z0[0], lin.t: 0.0}
    K_z = np.array(sym["K_z"].xreplace(values).evalf(), dtype=float).ravel()
    np.testing.assert_allclose(K_z, linear.K_z.ravel(), rtol=1e-12)
    assert K_z[0] == pytest.approx(-lin.model.parameters["Ki"], rel=1e-12)
