"""Drivers whose law reads the state (a gear, a cam, a filtered reference): physics as the oracle.

A coordinate driver ``q_d = L(t, q, z)`` is a holonomic constraint enforced by ideal forces
(:mod:`flexkane.kane.driver_laws`): the independent derivation is ``sympy.physics.mechanics``'
KanesMethod with that configuration constraint and the driven speed dependent.
"""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp
from sympy.physics.mechanics import KanesMethod, Point, ReferenceFrame, RigidBody, dynamicsymbols, inertia

import flexkane
from flexkane.errors import ModelError

#: Two rigid links on revolute joints, the second driven by a law of the first's angle.
GEARED = """
name = "geared"
[parameters]
m1 = 1.0
m2 = 0.7
I1 = 0.05
I2 = 0.03
c = 0.5
g = 9.81
[gravity]
g = "g"
direction = [0, -1]
[bodies.a]
mass = "m1"
inertia = "I1"
points = {{ hinge = [-0.4, 0.0], tip = [0.4, 0.0] }}
[bodies.b]
mass = "m2"
inertia = "I2"
points = {{ hinge = [-0.3, 0.0] }}
[joints.sa]
type = "revolute"
parent = "ground"
child = "a"
child_point = "hinge"
[joints.sb]
type = "revolute"
parent = "a"
parent_point = "tip"
child = "b"
child_point = "hinge"
driver = {{ coordinate = "{law}" }}
[initial]
q_sa = 0.3
"""


def _kanes_method_accelerations(law):
    """u_sa' of the chain by KanesMethod with ``q_sb - law(q_sa, t) = 0``, as a function of (q_sa, u_sa, t)."""
    t = dynamicsymbols._t
    qa, qb, ua, ub = dynamicsymbols("qa qb ua ub")
    m1, m2, I1, I2, c, g = 1.0, 0.7, 0.05, 0.03, 0.5, 9.81
    N = ReferenceFrame("N")
    A = N.orientnew("A", "Axis", (qa, N.z))
    B = A.orientnew("B", "Axis", (qb, A.z))
    A.set_ang_vel(N, ua * N.z)
    B.set_ang_vel(A, ub * A.z)
    O = Point("O")
    O.set_vel(N, 0)
    Ac = O.locatenew("Ac", 0.4 * A.x)
    Ac.v2pt_theory(O, N, A)
    hinge = O.locatenew("H", 0.8 * A.x)
    hinge.v2pt_theory(O, N, A)
    Bc = hinge.locatenew("Bc", 0.3 * B.x)
    Bc.v2pt_theory(hinge, N, B)
    bodies = [RigidBody("a", Ac, A, m1, (inertia(A, 0, 0, I1), Ac)),
              RigidBody("b", Bc, B, m2, (inertia(B, 0, 0, I2), Bc))]
    loads = [(Ac, -m1 * g * N.y), (Bc, -m2 * g * N.y)]
    L = law(qa, t, c)
    kane = KanesMethod(N, q_ind=[qa], q_dependent=[qb], u_ind=[ua], u_dependent=[ub],
                       kd_eqs=[qa.diff(t) - ua, qb.diff(t) - ub],
                       configuration_constraints=[qb - L],
                       velocity_constraints=[ub - L.diff(t).subs(qa.diff(t), ua)])
    kane.kanes_equations(bodies, loads)
    X = sp.symbols("QA QB UA UB T")
    plain = dict(zip([qa, qb, ua, ub, t], X))
    M, f = (sp.lambdify(X, e.xreplace(plain), "numpy") for e in (kane.mass_matrix, kane.forcing))
    speed = sp.lambdify([X[0], X[2], X[4]], L.diff(t).subs(qa.diff(t), ua).xreplace(plain), "numpy")
    angle = sp.lambdify([X[0], X[4]], L.xreplace(plain), "numpy")

    def accelerations(q, u, time):
        state = (q, angle(q, time), u, speed(q, u, time), time)
        return np.linalg.solve(np.atleast_2d(M(*state)), np.ravel(f(*state)))[0]
    return accelerations


def _flexkane_accelerations(eom):
    values = eom.constant_values()
    M, f = (sp.lambdify([*eom.q, *eom.u, eom.t], e.xreplace(values), "numpy") for e in (eom.mass_matrix, eom.forcing))
    return lambda *state: np.linalg.solve(np.atleast_2d(M(*state)), np.ravel(f(*state)))[0]


def test_a_gear_law_is_kanes_method_with_the_holonomic_constraint():
    """A gear ``q_sb = c q_sa`` with a cam term and a term of t: u_sa' at random states to 1e-10."""
    text = "c*q_sa + 0.2*sin(q_sa) + 0.1*sin(2*t)"

    def law(qa, t, c):
        return c * qa + 0.2 * sp.sin(qa) + 0.1 * sp.sin(2 * t)

    eom = flexkane.derive(flexkane.loads_model(GEARED.format(law=text)))
    assert [q.name for q in eom.q] == ["q_sa"] and [u.name for u in eom.u] == ["u_sa"]
    ours, theirs = _flexkane_accelerations(eom), _kanes_method_accelerations(law)
    rng = np.random.default_rng(18)
    for qa, ua, t in rng.uniform(-2.0, 2.0, size=(6, 3)):
        expected = theirs(qa, ua, t)
        assert abs(ours(qa, ua, t) - expected) <= 1e-10 * max(1.0, abs(expected))
