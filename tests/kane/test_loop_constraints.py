"""Closed kinematic loops (issue 9): dependent speeds, consistent initial conditions, drift, power.

The rigid four-bar is checked against an independent ``sympy.physics.mechanics`` derivation with
dependent speeds; the flexible slider-crank against the rigid mechanism and the power balance.
"""

import numpy as np
import pytest
import sympy as sp
import sympy.physics.mechanics as me
from scipy.integrate import cumulative_trapezoid

import flexkane

RTOL, ATOL = 1e-10, 1e-12


@pytest.fixture(scope="module")
def four_bar():
    model = flexkane.builtin_model("four-bar")
    eom = flexkane.derive(model)
    return model, eom, flexkane.compile_model(eom)


def sympy_four_bar(par):
    """The four-bar with KanesMethod, q_crank independent, the loop closed by two constraints."""
    q1, q2, q3 = me.dynamicsymbols("q1 q2 q3")
    u1, u2, u3 = me.dynamicsymbols("u1 u2 u3")
    a, b, c, d = par["a"], par["b"], par["c"], par["d"]
    m1, m2, m3, g = par["m1"], par["m2"], par["m3"], par["g"]
    N = me.ReferenceFrame("N")
    A = N.orientnew("A", "Axis", [q1, N.z])
    B = A.orientnew("B", "Axis", [q2, A.z])
    C = N.orientnew("C", "Axis", [q3, N.z])
    A.set_ang_vel(N, u1 * N.z)
    B.set_ang_vel(A, u2 * A.z)
    C.set_ang_vel(N, u3 * N.z)
    O = me.Point("O")
    O.set_vel(N, 0)
    Ao = O.locatenew("Ao", a / 2 * A.x)
    Ao.v2pt_theory(O, N, A)
    P = O.locatenew("P", a * A.x)
    P.v2pt_theory(O, N, A)
    Bo = P.locatenew("Bo", b / 2 * B.x)
    Bo.v2pt_theory(P, N, B)
    Btip = P.locatenew("Bt", b * B.x)
    Btip.v2pt_theory(P, N, B)
    O4 = O.locatenew("O4", d * N.x)
    O4.set_vel(N, 0)
    Co = O4.locatenew("Co", c / 2 * C.x)
    Co.v2pt_theory(O4, N, C)
    Ctip = O4.locatenew("Ct", c * C.x)
    Ctip.v2pt_theory(O4, N, C)
    loop = Btip.pos_from(O) - Ctip.pos_from(O)
    config = [loop.dot(N.x), loop.dot(N.y)]
    vel = [(Btip.vel(N) - Ctip.vel(N)).dot(N.x), (Btip.vel(N) - Ctip.vel(N)).dot(N.y)]
    bodies = [me.RigidBody("A", Ao, A, m1, (me.inertia(A, 0, 0, m1 * a ** 2 / 12), Ao)),
              me.RigidBody("B", Bo, B, m2, (me.inertia(B, 0, 0, m2 * b ** 2 / 12), Bo)),
              me.RigidBody("C", Co, C, m3, (me.inertia(C, 0, 0, m3 * c ** 2 / 12), Co))]
    loads = [(Ao, -m1 * g * N.y), (Bo, -m2 * g * N.y), (Co, -m3 * g * N.y)]
    kane = me.KanesMethod(N, [q1], [u1], kd_eqs=[q1.diff() - u1, q2.diff() - u2, q3.diff() - u3],
                          q_dependent=[q2, q3], configuration_constraints=config,
                          u_dependent=[u2, u3], velocity_constraints=vel)
    kane.kanes_equations(bodies, loads)
    return kane, (q1, q2, q3), (u1, u2, u3)


def test_rigid_four_bar_matches_sympy_mechanics_with_dependent_speeds(four_bar):
    model, eom, compiled = four_bar
    par = {k: float(v) for k, v in model.parameters.items() if not isinstance(v, str)}
    kane, qs, us = sympy_four_bar(par)
    assert [s.name for s in eom.u] == ["u_crank"]
    p = eom.parameter_vector()
    Mf = kane.mass_matrix_full
    Ff = kane.forcing_full
    for crank, rate in ((1.0, 3.0), (2.5, -1.0), (4.0, 0.5)):
        y = eom.initial_state(model)
        y[[q.name for q in eom.q].index("q_crank")] = crank
        y[: len(eom.q)] = eom.project_coordinates(y[: len(eom.q)], eom.constant_values())
        y[len(eom.q)] = rate
        ours = compiled.rhs(0.0, y, p)[len(eom.q)]
        q = dict(zip([s.name for s in eom.q], y))
        qv = [q["q_crank"], q["q_coupler"], q["q_rocker"]]
        # dependent speeds from the velocity constraints
        values = eom.constant_values()
        deps = {s.name: float(expr.subs({**values, **dict(zip(eom.q, y[:3])), eom.u[0]: rate}).evalf())
                for s, expr in eom.dependent_speeds.items()}
        uv = [rate, deps["u_coupler"], deps["u_rocker"]]
        subs = dict(zip(qs, qv)) | dict(zip(us, uv))
        xdot = np.linalg.solve(np.array(me.msubs(Mf, subs).evalf(), dtype=float),
                               np.array(me.msubs(Ff, subs).evalf(), dtype=float).ravel())
        assert abs(ours - xdot[3]) < 1e-9 * max(1.0, abs(xdot[3]))


def test_loop_closure_keeps_the_crank_angle_the_user_set(four_bar):
    """The closure solves for the coupler and rocker angles only (kane.loop_closure): the crank
    angle is returned bit for bit, from near and far guesses of the others, the loop closed."""
    from flexkane.kane.loop_closure import closure_unknowns

    model, eom, compiled = four_bar
    names = [q.name for q in eom.q]
    assert sorted(q.name for q in closure_unknowns(eom)) == ["q_coupler", "q_rocker"]
    values = eom.constant_values()
    guess = eom.initial_state(model)[: len(eom.q)]
    crank = names.index("q_crank")
    for angle, offset in ((0.1 + 1e-3, 0.0), (2.5, 0.3), (4.0, -0.2)):
        q = guess.copy()
        q[crank] = angle
        q[[names.index("q_coupler"), names.index("q_rocker")]] += offset
        closed = eom.project_coordinates(q.copy(), values)
        assert closed[crank].tobytes() == q[crank].tobytes()
        phi = [float(e.xreplace({**values, **dict(zip(eom.q, closed))})) for e in eom._phi]
        assert max(abs(v) for v in phi) <= 1e-12, phi


def test_four_bar_conserves_energy_and_keeps_its_loop_closed(four_bar):
    model, eom, compiled = four_bar
    res = flexkane.simulate(compiled, t_end=2.0, dt_out=2e-3, rtol=RTOL, atol=ATOL)
    e = res["energy"]
    assert np.abs(e - e[0]).max() < 1e-8 * np.abs(res["kinetic"]).max()
    residual = max(np.abs(res[k]).max() for k in res.outputs if k.startswith("constraint_"))
    assert residual < 1e-9


@pytest.fixture(scope="module")
def slider_crank():
    model = flexkane.builtin_model("slider-crank")
    compiled = flexkane.compile_model(flexkane.derive(model))
    return flexkane.simulate(compiled, t_end=0.02, dt_out=2.5e-6, rtol=RTOL, atol=ATOL)


def test_slider_crank_constraint_residual_stays_at_solver_tolerance(slider_crank):
    names = [k for k in slider_crank.outputs if k.startswith("constraint_")]
    assert len(names) == 2
    assert max(np.abs(slider_crank[k]).max() for k in names) < 1e-10


def test_slider_crank_crank_drive_power_equals_rate_of_kinetic_plus_strain_energy(slider_crank):
    e = slider_crank["kinetic"] + slider_crank["strain"]
    work = cumulative_trapezoid(slider_crank["power_nonconservative"], slider_crank.t, initial=0.0)
    assert np.abs(slider_crank["effort_crank"]).max() > 0.1
    assert np.abs(e - e[0] - work).max() < 1e-5 * np.abs(e).max()
    # integrated with the motion, the crank's work (its effort against the constraint forces
    # included) balances the energy to the solver's tolerance
    assert np.abs(slider_crank["energy_balance"]).max() < 1e-9 * np.abs(slider_crank["energy"]).max()


def test_slider_crank_follows_the_rigid_mechanism_to_the_order_of_the_elastic_deflection(slider_crank):
    theta = 150.0 * slider_crank.t
    L1, L2 = 0.15, 0.30
    rigid = L1 * np.cos(theta) + np.sqrt(L2 ** 2 - (L1 * np.sin(theta)) ** 2)
    gap = np.abs(slider_crank["q_slider"] - rigid).max()
    deflection = max(np.abs(slider_crank[k]).max() for k in ("q_rod_1", "q_rod_2", "s_rod_1", "s_rod_2"))
    assert deflection > 0
    assert gap < 10 * deflection + 1e-9
    assert gap < 1e-3          # well below a millimetre on a 0.45 m stroke


def test_published_smooth_initial_values_start_the_slider_crank_without_high_frequency_vibration():
    """The test set's initial values for the smooth solution (consistent with the loop: flexkane closes
    it from them to 1e-10) excite the rod's fast modes far less than a rod started undeformed."""
    model = flexkane.builtin_model("slider-crank")
    eom = flexkane.derive(model)
    y0 = eom.initial_state(model)
    assert abs(y0[eom.state_names.index("q_slider")] - 0.450016933) < 1e-9
    compiled = flexkane.compile_model(eom)
    undeformed = model.copy()
    undeformed.initial = {"q_slider": 0.45}
    curvature = {}
    for name, variant in (("smooth", model), ("undeformed", undeformed)):
        res = flexkane.simulate(compiled, t_end=0.03, dt_out=1e-5, rtol=1e-9, atol=1e-12, model=variant)
        x = res["s_rod_2"]
        curvature[name] = np.abs(x[2:] - 2 * x[1:-1] + x[:-2]).max() / 1e-10   # max |s''| [m/s^2]
    assert curvature["smooth"] < 0.05 * curvature["undeformed"]
