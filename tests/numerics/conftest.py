"""Models and compiled modules shared by the numerics tests.

Every model is an equations-of-motion namespace like the one the derivation produces (``t``,
``q``, ``u``, ``constants``, ``qdot``, ``mass_matrix``, ``forcing``). Compiled modules are
session-scoped: Numba compilation dominates the run time of these tests. They go to the session's one
cache directory (tests/conftest.py), which the other folders' tests share: a structure is compiled
once per session, not once before and once after these tests.
"""

from __future__ import annotations

import types

import numpy as np
import pytest
import sympy as sp
from sympy.physics import mechanics as me

from flexkane.numerics import build_module, generate_outputs_source, generate_rhs_source, \
    structure_key


def eom_namespace(t, q, u, constants, qdot, mass_matrix, forcing):
    """Equations of motion as the derivation delivers them."""
    return types.SimpleNamespace(t=t, q=list(q), u=list(u), constants=list(constants),
                                 qdot=sp.Matrix(qdot), mass_matrix=sp.Matrix(mass_matrix),
                                 forcing=sp.Matrix(forcing))


def compile_eom(eom, outputs=None):
    """Generate, write and import the module of ``eom`` (with ``outputs`` if given)."""
    source = generate_rhs_source(eom)
    if outputs:
        source += "\n\n" + generate_outputs_source(outputs, eom)
    return build_module(source, structure_key(source))


def harmonic_oscillator():
    """Mass m on a spring k:  m x'' = -k x  (x = q, x' = u).

    ::

        |--/\\/\\/\\--[m]--> x
    """
    t, x, v, m, k = sp.symbols("t x v m k")
    eom = eom_namespace(t, [x], [v], [m, k], [v], [[m]], [-k * x])
    eom.ud = [sp.Symbol("vd")]
    return eom


def pendulum():
    """Simple pendulum of length l, angle theta from the downward vertical, mass m."""
    t, th, w, m, l, g = sp.symbols("t theta omega m l g")
    return eom_namespace(t, [th], [w], [m, l, g], [w], [[m * l ** 2]], [-m * g * l * sp.sin(th)])


def double_pendulum():
    """Double pendulum of point masses by sympy's KanesMethod (q1, q2 absolute angles).

    ::

        ----o----  N
            \\  l1
             m1
              \\ l2
               m2
    """
    q1, q2 = me.dynamicsymbols("q1 q2")
    u1, u2 = me.dynamicsymbols("u1 u2")
    m1, m2, l1, l2, g = sp.symbols("m1 m2 l1 l2 g")
    t = me.dynamicsymbols._t
    N = me.ReferenceFrame("N")
    A = N.orientnew("A", "Axis", [q1, N.z])
    B = N.orientnew("B", "Axis", [q2, N.z])
    A.set_ang_vel(N, u1 * N.z)
    B.set_ang_vel(N, u2 * N.z)
    O = me.Point("O")
    O.set_vel(N, 0)
    P = O.locatenew("P", l1 * A.x)
    R = P.locatenew("R", l2 * B.x)
    P.v2pt_theory(O, N, A)
    R.v2pt_theory(P, N, B)
    particles = [me.Particle("Pa", P, m1), me.Particle("Ra", R, m2)]
    loads = [(P, m1 * g * N.x), (R, m2 * g * N.x)]
    kane = me.KanesMethod(N, q_ind=[q1, q2], u_ind=[u1, u2],
                          kd_eqs=[q1.diff(t) - u1, q2.diff(t) - u2])
    kane.kanes_equations(particles, loads)
    plain = {f: sp.Symbol(f.func.__name__) for f in (q1, q2, u1, u2)}
    ts = sp.Symbol("t")
    mass = kane.mass_matrix.xreplace(plain)
    forcing = kane.forcing.xreplace(plain)
    qs = [plain[q1], plain[q2]]
    us = [plain[u1], plain[u2]]
    return eom_namespace(ts, qs, us, [m1, m2, l1, l2, g], us, mass, forcing)


def stiff_chain(n_masses=4):
    """Chain of masses m_i joined by springs k_i and dashpots c_i to the wall and each other.

    ::

        |--k1,c1--[m1]--k2,c2--[m2]-- ... --[mn]

    Forcing ``-K q - C u``; with large ``c`` the fast modes are overdamped (real eigenvalues).
    """
    t = sp.Symbol("t")
    q = sp.symbols(f"x1:{n_masses + 1}")
    u = sp.symbols(f"v1:{n_masses + 1}")
    m = sp.symbols(f"m1:{n_masses + 1}")
    k = sp.symbols(f"k1:{n_masses + 1}")
    c = sp.symbols(f"c1:{n_masses + 1}")
    forcing = []
    for i in range(n_masses):
        left_q = q[i - 1] if i else 0
        left_u = u[i - 1] if i else 0
        f = -k[i] * (q[i] - left_q) - c[i] * (u[i] - left_u)
        if i + 1 < n_masses:
            f += k[i + 1] * (q[i + 1] - q[i]) + c[i + 1] * (u[i + 1] - u[i])
        forcing.append(f)
    return eom_namespace(t, q, u, [*m, *k, *c], u, sp.diag(*m), forcing)


def troubled_slider():
    """Slider whose mass is its coordinate:  q' = -a + e q**2,  q u' = q b.

    Three ways to fail, by the constants (a, e, b):

    * ``q(0) = 0``: the mass matrix [[q]] is singular at the start;
    * ``a = 1, e = 0, q(0) = 1``: ``q = 1 - t``, singular at ``t = 1`` while ``u = b t``;
    * ``a = 0, e = 1, q(0) = 1``: ``q = 1 / (1 - t)`` blows up at ``t = 1``.
    """
    t, q, u, a, e, b = sp.symbols("t q u a e b")
    return eom_namespace(t, [q], [u], [a, e, b], [-a + e * q ** 2], [[q]], [q * b])


# Constants of stiff_chain(): masses [kg], springs [N/m], dashpots [N s/m].
# Strong dashpots between masses 1-2 and 3-4: real eigenvalues near -1e6, slow modes ~5-11 rad/s.
STIFF_CHAIN_CONSTANTS = np.array([1, 1, 1, 1, 100, 100, 100, 100, 1, 5e5, 1, 5e5], float)
# Lightly damped stiff springs (a lumped-mass bar, i.e. a mildly stiff beam): modes up to
# about 1.2e3 rad/s with damping ratios below 0.3 %.
BAR_CONSTANTS = np.array([1, 1, 1, 1, 4e5, 4e5, 4e5, 4e5, 2, 2, 2, 2], float)
STIFF_CHAIN_Y0 = np.array([0.1, -0.2, 0.3, 0.0, 0.0, 1.0, 0.0, -1.0])


@pytest.fixture(scope="session")
def models():
    """The model builders and helpers of this file, for tests that need more than a module."""
    return types.SimpleNamespace(
        eom=eom_namespace, compile=compile_eom, harmonic_oscillator=harmonic_oscillator,
        pendulum=pendulum, double_pendulum=double_pendulum, stiff_chain=stiff_chain,
        stiff_chain_matrix=stiff_chain_matrix, troubled_slider=troubled_slider,
        STIFF_CHAIN_CONSTANTS=STIFF_CHAIN_CONSTANTS,
        BAR_CONSTANTS=BAR_CONSTANTS, STIFF_CHAIN_Y0=STIFF_CHAIN_Y0)


@pytest.fixture(scope="session")
def oscillator_module():
    eom = harmonic_oscillator()
    m, k = eom.constants
    x, v = eom.q[0], eom.u[0]
    return compile_eom(eom, {"energy": m * v ** 2 / 2 + k * x ** 2 / 2, "x2": 2 * x,
                             "spring_force": -m * eom.ud[0]})


@pytest.fixture(scope="session")
def pendulum_module():
    return compile_eom(pendulum())


@pytest.fixture(scope="session")
def double_pendulum_eom():
    return double_pendulum()


@pytest.fixture(scope="session")
def double_pendulum_module(double_pendulum_eom):
    return compile_eom(double_pendulum_eom)


@pytest.fixture(scope="session")
def stiff_chain_module():
    return compile_eom(stiff_chain())


def stiff_chain_matrix(p, n_masses=4):
    """First-order system matrix A (2n, 2n) of :func:`stiff_chain` for constants ``p``."""
    m, k, c = p[:n_masses], p[n_masses:2 * n_masses], p[2 * n_masses:]
    K = np.zeros((n_masses, n_masses))
    C = np.zeros((n_masses, n_masses))
    for i in range(n_masses):
        K[i, i] += k[i]
        C[i, i] += c[i]
        if i + 1 < n_masses:
            K[i, i] += k[i + 1]
            K[i, i + 1] -= k[i + 1]
            K[i + 1, i] -= k[i + 1]
            K[i + 1, i + 1] += 0.0
            C[i, i] += c[i + 1]
            C[i, i + 1] -= c[i + 1]
            C[i + 1, i] -= c[i + 1]
    Minv = np.diag(1.0 / np.asarray(m))
    A = np.zeros((2 * n_masses, 2 * n_masses))
    A[:n_masses, n_masses:] = np.eye(n_masses)
    A[n_masses:, :n_masses] = -Minv @ K
    A[n_masses:, n_masses:] = -Minv @ C
    return A


@pytest.fixture(scope="session")
def troubled_slider_module():
    return compile_eom(troubled_slider())
