"""Rigid chains: flexkane's mass matrix and forcing equal an independent derivation with
``sympy.physics.mechanics.KanesMethod`` (issue 3, rigid limit)."""

import numpy as np
import pytest
import sympy as sp
import sympy.physics.mechanics as me

import flexkane

MODEL = """
name = "rigid-chain"
[parameters]
mA = 1.3
IA = 0.11
a = 0.4
bA = 0.35
mB = 0.7
IB = 0.05
c = 0.3
dB = 0.25
mC = 0.4
IC = 0.02
alpha = 0.3
k2 = 3.0
c2 = 0.2
kC = 8.0
g = 9.81
tau0 = 0.5

[bodies.A]
mass = "mA"
inertia = "IA"
points = { pivot = ["-a", 0], tip = ["bA", 0] }

[bodies.B]
mass = "mB"
inertia = "IB"
points = { hinge = ["-c", 0], rail = ["dB", 0] }

[bodies.C]
mass = "mC"
inertia = "IC"

[joints.shoulder]
type = "revolute"
parent = "ground"
child = "A"
child_point = "pivot"
torque = "tau0*sin(3*t)"

[joints.elbow]
type = "revolute"
parent = "A"
parent_point = "tip"
child = "B"
child_point = "hinge"
stiffness = "k2"
damping = "c2"

[joints.slider]
type = "prismatic"
parent = "B"
parent_point = "rail"
child = "C"
axis = "alpha"
stiffness = "kC"

[gravity]
g = "g"
direction = [0, -1]
"""


def sympy_mechanics_chain():
    """The same chain written directly with sympy.physics.mechanics (an independent derivation)."""
    q1, q2, q3 = me.dynamicsymbols("q1 q2 q3")
    u1, u2, u3 = me.dynamicsymbols("u1 u2 u3")
    t = me.dynamicsymbols._t
    S = lambda n: sp.Symbol(n, real=True)  # noqa: E731
    mA, IA, a, bA, mB, IB, c, dB, mC, IC, alpha, k2, c2, kC, g, tau0 = map(
        S, "mA IA a bA mB IB c dB mC IC alpha k2 c2 kC g tau0".split())
    N = me.ReferenceFrame("N")
    A = N.orientnew("A", "Axis", [q1, N.z])
    B = A.orientnew("B", "Axis", [q2, A.z])
    A.set_ang_vel(N, u1 * N.z)
    B.set_ang_vel(A, u2 * A.z)
    O = me.Point("O")
    O.set_vel(N, 0)
    Ao = O.locatenew("Ao", a * A.x)
    Ao.v2pt_theory(O, N, A)
    Ej = Ao.locatenew("Ej", bA * A.x)
    Ej.v2pt_theory(Ao, N, A)
    Bo = Ej.locatenew("Bo", c * B.x)
    Bo.v2pt_theory(Ej, N, B)
    R = Bo.locatenew("R", dB * B.x)
    R.v2pt_theory(Bo, N, B)
    axis = sp.cos(alpha) * B.x + sp.sin(alpha) * B.y
    Co = R.locatenew("Co", q3 * axis)
    Co.set_vel(B, u3 * axis)
    Co.v1pt_theory(R, N, B)
    bodies = [me.RigidBody("A", Ao, A, mA, (me.inertia(A, 0, 0, IA), Ao)),
              me.RigidBody("B", Bo, B, mB, (me.inertia(B, 0, 0, IB), Bo)),
              me.RigidBody("C", Co, B, mC, (me.inertia(B, 0, 0, IC), Co))]
    loads = [(Ao, -mA * g * N.y), (Bo, -mB * g * N.y), (Co, -mC * g * N.y),
             (A, tau0 * sp.sin(3 * t) * N.z),
             (B, (-k2 * q2 - c2 * u2) * A.z), (A, (k2 * q2 + c2 * u2) * A.z),
             (Co, -kC * q3 * axis), (R, kC * q3 * axis)]
    kane = me.KanesMethod(N, [q1, q2, q3], [u1, u2, u3], kd_eqs=[q1.diff() - u1, q2.diff() - u2, q3.diff() - u3])
    kane.kanes_equations(bodies, loads)
    return kane, (q1, q2, q3), (u1, u2, u3), t


def test_rigid_chain_mass_matrix_and_forcing_equal_sympy_mechanics():
    model = flexkane.loads_model(MODEL)
    eom = flexkane.derive(model)
    kane, qs, us, t = sympy_mechanics_chain()
    assert [q.name for q in eom.q] == ["q_shoulder", "q_elbow", "q_slider"]
    rng = np.random.default_rng(7)
    params = eom.constant_values(model)
    for _ in range(5):
        qv, uv, tv = rng.normal(size=3), rng.normal(size=3), rng.uniform(0, 2)
        ours = {**{s: v for s, v in zip(eom.q, qv)}, **{s: v for s, v in zip(eom.u, uv)}, eom.t: tv}
        ours.update(params)
        theirs = {**{s: v for s, v in zip(qs, qv)}, **{s: v for s, v in zip(us, uv)}, t: tv}
        theirs.update({sp.Symbol(k, real=True): v for k, v in model.parameters.items()})
        M1 = np.array(eom.mass_matrix.subs(ours).evalf(), dtype=float)
        f1 = np.array(eom.forcing.subs(ours).evalf(), dtype=float).ravel()
        M2 = np.array(me.msubs(kane.mass_matrix, theirs).evalf(), dtype=float)
        f2 = np.array(me.msubs(kane.forcing, theirs).evalf(), dtype=float).ravel()
        np.testing.assert_allclose(M1, M2, rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(f1, f2, rtol=1e-12, atol=1e-12)


def test_results_do_not_depend_on_the_order_in_which_parts_are_listed():
    base = flexkane.loads_model(MODEL)
    shuffled = base.copy()
    shuffled.bodies = dict(reversed(list(shuffled.bodies.items())))
    shuffled.joints = dict(reversed(list(shuffled.joints.items())))
    e1, e2 = flexkane.derive(base), flexkane.derive(shuffled)
    assert [s.name for s in e1.q] == [s.name for s in e2.q]
    assert sp.simplify(e1.mass_matrix - e2.mass_matrix) == sp.zeros(3, 3)
    assert sp.simplify(e1.forcing - e2.forcing) == sp.zeros(3, 1)
