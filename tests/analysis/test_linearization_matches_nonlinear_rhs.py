"""The linear model agrees with finite differences of the compiled nonlinear right-hand side.

Central differences of ``compiled.rhs(t, y, p)`` at the operating point, with respect to the state
(dq, du) and to the inputs (entries of p), give A and B_ss to O(h^2); the symbolic Jacobians of
SymPy give the same numbers as the factored forward Jacobians used for them.
"""

import numpy as np
import sympy as sp

import flexkane
from flexkane import Model
from flexkane.analysis import Linearization, modal_analysis
from flexkane.analysis.jacobian import forward_jacobian
from flexkane.model.parts import Beam, Gravity, Joint, Load, RigidBody


def sprung_flexible_pendulum():
    """A flexible rod with a tip body on a sprung, damped pivot, under gravity, pushed at the tip.

    The spring's rest angle tilts the equilibrium away from the vertical, so the rod is bent by
    its weight there and every matrix (M, C, K, B) is full.
    """
    model = Model(name="sprung-pendulum", parameters={
        "L": 0.9, "EI": 15.0, "rho": 0.7, "g": 9.81, "k": 20.0, "c": 0.3, "rest": 0.8,
        "m_tip": 0.4, "J_tip": 2e-3, "F0": 0.5, "zeta": 0.02})
    model.beams["rod"] = Beam(name="rod", L="L", EI="EI", rho="rho", n_modes=3, damping=["zeta"])
    model.bodies["tip"] = RigidBody(name="tip", mass="m_tip", inertia="J_tip")
    model.joints["pivot"] = Joint(name="pivot", type="revolute", parent="ground", child="rod",
                                  angle="-pi/2", stiffness="k", damping="c", rest="rest")
    model.joints["weld"] = Joint(name="weld", type="weld", parent="rod", station="L", child="tip")
    model.gravity = Gravity(g="g", direction=(0, -1))
    model.loads["push"] = Load(name="push", body="tip", force=("F0", "F0*t"), frame="local")
    return model


def central_differences(function, x, steps):
    columns = []
    for k, h in enumerate(steps):
        e = np.zeros_like(x)
        e[k] = h
        columns.append((function(x + e) - function(x - e)) / (2 * h))
    return np.column_stack(columns)


def test_state_space_matrices_match_finite_differences_at_a_bent_equilibrium():
    lin = Linearization(sprung_flexible_pendulum())
    linear = lin.at()
    assert any("depend explicitly on time" in note for note in lin.notes)    # the load F0 t
    assert linear.input_names == ["input_effort_pivot", "input_load_push_fx", "input_load_push_fy"]
    np.testing.assert_allclose(linear.r0, [0.0, 0.5, 0.0])         # no torque field; F0 and F0 t at t0 = 0
    assert abs(linear.q0[0]) > 0.1 and np.max(np.abs(linear.q0[1:])) > 1e-4   # tilted and bent
    A, Bss = linear.state_space()
    eom = lin.eom                                                    # the model with inputs as parameters
    compiled = flexkane.compile_model(eom)
    p = eom.parameter_vector(lin.model)
    y0 = np.concatenate([linear.q0, np.zeros(linear.n)])
    assert np.max(np.abs(compiled.rhs(0.0, y0, p))) < 1e-9           # an equilibrium of the nonlinear model
    A_fd = central_differences(lambda y: compiled.rhs(0.0, y, p), y0, np.full(y0.size, 1e-6))
    np.testing.assert_allclose(A, A_fd, atol=1e-6 * np.abs(A).max())
    index = [[s.name for s in eom.constants].index(name) for name in linear.input_names]

    def with_inputs(r):
        q = p.copy()
        q[index] = r
        return compiled.rhs(0.0, y0, q)

    B_fd = central_differences(with_inputs, p[index], np.full(len(index), 1e-5))
    np.testing.assert_allclose(Bss, B_fd, atol=1e-7 * np.abs(Bss).max())
    # damped: every mode decays
    modal = modal_analysis(linear)
    assert all(m.kind == "oscillatory" and m.damping_ratio > 0 for m in modal.modes)


def test_steady_spin_linearization_matches_the_driven_model_after_spin_up():
    """spin-up holds Omega = 6 rad/s after T = 15 s: its rhs at t = 16 s is the steady spin's."""
    model = flexkane.builtin_model("spin-up").with_modes(2)
    linear = Linearization(model, about="spin", spin=6.0).at()
    assert linear.dropped == {"q_hub": "cyclic"}
    A, _ = linear.state_space()
    eom = flexkane.derive(model)
    compiled = flexkane.compile_model(eom)
    p = eom.parameter_vector()
    assert [q.name for q in eom.q] == ["q_hub"] + linear.coordinates
    y0 = np.zeros(len(eom.q) + len(eom.u))
    A_fd = central_differences(lambda y: compiled.rhs(16.0, y, p), y0, np.full(y0.size, 1e-6))
    keep = np.arange(1, y0.size)                                     # without q_hub
    np.testing.assert_allclose(A_fd[:, 0], 0.0, atol=1e-12)          # q_hub is cyclic
    np.testing.assert_allclose(A, A_fd[np.ix_(keep, keep)], atol=1e-6 * np.abs(A).max())


def test_symbolic_jacobians_give_the_numeric_matrices():
    lin = Linearization(flexkane.builtin_model("flexible-arm").with_modes(2))
    linear = lin.at()
    symbolic = lin.symbolic_matrices()
    args = [*lin.q, *lin.dropped, lin.t, *lin.parameters]
    values = [*linear.q0, *lin.dropped_values, lin.t0, *lin.p]
    for name in ("M", "C", "K", "B", "W", "V"):
        number = np.array(sp.lambdify(args, symbolic[name])(*values), dtype=float)
        np.testing.assert_allclose(number, getattr(linear, name), rtol=1e-12, atol=1e-12, err_msg=name)


def test_forward_jacobian_equals_sympy_jacobian():
    x, y, z, a = sp.symbols("x y z a")
    exprs = [sp.sin(x * y) ** 2 + a * sp.exp(z) / (1 + x ** 2),
             sp.sqrt(1 + y ** 2) * sp.cos(x + z) - x ** a,
             sp.Piecewise((x * y, a > 1), (z ** 3, True)) + sp.sin(x * y) * z]
    fj = forward_jacobian(exprs, [x, y, z])
    f = sp.lambdify([x, y, z, a], [fj.values, fj.jacobian], cse=fj.cse)
    reference = sp.lambdify([x, y, z, a], [exprs, sp.Matrix(exprs).jacobian([x, y, z])])
    for point in ([0.3, -1.2, 0.7, 2.0], [1.1, 0.4, -0.5, 0.5]):
        values, jacobian = f(*point)
        ref_values, ref_jacobian = reference(*point)
        np.testing.assert_allclose(np.array(values, dtype=float), np.array(ref_values, dtype=float), rtol=1e-14)
        np.testing.assert_allclose(np.array(jacobian, dtype=float), np.array(ref_jacobian, dtype=float),
                                   rtol=1e-13, atol=1e-15)
