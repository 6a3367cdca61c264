"""Generalized inertia forces F*_r (eq. 8.22).

    F*_r = w_r . (-I alpha) + v_r . (-m a)        for every rigid body,
         + int_0^L v_P,r . (-a_P) rho dx          for every beam,

with ``a = sum_s v_s u_s' + a_rem``. Split accordingly, ``F*_r = -sum_s M_rs u_s' - Fhat_r`` where
``M_rs = sum m v_r . v_s + I w_r w_s + int rho v_P,r . v_P,s dx`` is the (symmetric) mass matrix.
"""

from __future__ import annotations

import sympy as sp

from .kinematics import Kinematics, rigid_vec
from .modal_field import ONE, vec_map

__all__ = ["InertiaForces", "generalized_inertia_forces"]


class InertiaForces:
    """The pieces of F*_r.

    Attributes
    ----------
    mass_matrix : sympy.Matrix, shape (n, n)
        ``M_rs`` for all speeds (driven ones included).
    remainder : list of sympy.Expr, length n
        ``Fhat_r``, so that ``F*_r = -sum_s M_rs u_s' - Fhat_r``.
    speeds : list of sympy.Symbol
        The speeds r, in order.
    """

    def __init__(self, mass_matrix: sp.Matrix, remainder: list, speeds: list):
        self.mass_matrix = mass_matrix
        self.remainder = remainder
        self.speeds = speeds

    def F_r_star(self, ud: dict) -> list[sp.Expr]:
        """F*_r with the symbols of u' (eq. 8.22, term by term as eq. 8.23)."""
        n = len(self.speeds)
        return [-sp.Add(*[self.mass_matrix[r, s] * ud[self.speeds[s]] for s in range(n)])
                - self.remainder[r] for r in range(n)]


def generalized_inertia_forces(kin: Kinematics) -> InertiaForces:
    """Mass matrix and remainder of F*_r for every body and beam of the chain.

    Parameters
    ----------
    kin : Kinematics

    Returns
    -------
    InertiaForces
    """
    chain = kin.chain
    model = chain.model
    speeds = chain.u
    n = len(speeds)
    M = [[sp.Integer(0)] * n for _ in range(n)]
    rem = [sp.Integer(0)] * n
    for name, frame in kin.bodies.items():
        body = model.bodies[name]
        m = kin.value(f"bodies.{name}.mass", body.mass, f"m_{name}")
        inertia = kin.value(f"bodies.{name}.inertia", body.inertia, f"I_{name}")
        vx, vy = frame.v
        Vx, Vy, W = ([chain.partial(e, u) for u in speeds] for e in (vx, vy, frame.omega))
        a_rem = kin.acceleration_remainder(rigid_vec(frame.v), frame.omega)
        ax, ay = a_rem[0].coefficient(("1",)), a_rem[1].coefficient(("1",))
        alpha = chain.dt(frame.omega)
        active = [r for r in range(n) if Vx[r] != 0 or Vy[r] != 0 or W[r] != 0]
        for i, r in enumerate(active):
            for s in active[i:]:
                M[r][s] += m * (Vx[r] * Vx[s] + Vy[r] * Vy[s]) + inertia * W[r] * W[s]
            rem[r] += m * (Vx[r] * ax + Vy[r] * ay) + inertia * W[r] * alpha
    for name, bm in kin.beams.items():
        consts = bm.constants
        V = [vec_map(bm.v, lambda c, u=u: chain.partial(c, u)) for u in speeds]
        a_rem = kin.acceleration_remainder(bm.v, bm.frame.omega)
        active = [r for r in range(n) if not (V[r][0].is_zero() and V[r][1].is_zero())]
        # Speeds that do not deform the beam (all but its own modal speeds) move it as a rigid body:
        # V_r(x) = A_r + W_r k x p(x). Their terms use the beam's mass, first moment S and moment of
        # inertia J about its root, and the resultant R and moment K of rho a_rem, each named once:
        # no sum over the shape functions per pair of speeds.
        own = {c.u for c in chain.of(name)}
        rigid = [r for r in active if speeds[r] not in own]
        if rigid:
            m = consts.pair(ONE, ONE)
            Sx = chain.name(consts.integrate1(bm.X), f"Sx_{name}")
            Sy = chain.name(consts.integrate1(bm.Y), f"Sy_{name}")
            J = chain.name(consts.integrate(bm.X, bm.X) + consts.integrate(bm.Y, bm.Y), f"J_{name}")
            Rx = chain.name(consts.integrate1(a_rem[0]), f"Rx_{name}")
            Ry = chain.name(consts.integrate1(a_rem[1]), f"Ry_{name}")
            K = chain.name(consts.integrate(bm.X, a_rem[1]) - consts.integrate(bm.Y, a_rem[0]), f"K_{name}")
            A = {r: (chain.partial(bm.frame.v[0], speeds[r]), chain.partial(bm.frame.v[1], speeds[r]))
                 for r in rigid}
            W = {r: chain.partial(bm.frame.omega, speeds[r]) for r in rigid}
            lever = {r: -A[r][0] * Sy + A[r][1] * Sx for r in rigid}    # int rho A_r . (k x p) dx
        for i, r in enumerate(active):
            for s in active[i:]:
                if r in rigid and s in rigid:
                    M[r][s] += (m * (A[r][0] * A[s][0] + A[r][1] * A[s][1]) + W[s] * lever[r]
                                + W[r] * lever[s] + W[r] * W[s] * J)
                else:
                    M[r][s] += consts.integrate(V[r][0], V[s][0]) + consts.integrate(V[r][1], V[s][1])
            if r in rigid:
                rem[r] += A[r][0] * Rx + A[r][1] * Ry + W[r] * K
            else:
                rem[r] += consts.integrate(V[r][0], a_rem[0]) + consts.integrate(V[r][1], a_rem[1])
    for r in range(n):
        for s in range(r):
            M[r][s] = M[s][r]
    return InertiaForces(sp.Matrix(M), rem, speeds)

