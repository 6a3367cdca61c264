"""Generalized inertia forces F*_r (eq. 8.22).

    F*_r = w_r . (-I alpha) + v_r . (-m a)        for every rigid body,
         + int_0^L v_P,r . (-a_P) rho dx          for every beam,

with ``a = sum_s v_s u_s' + a_rem``. Split accordingly, ``F*_r = -sum_s M_rs u_s' - Fhat_r`` where
``M_rs = sum m v_r . v_s + I w_r w_s + int rho v_P,r . v_P,s dx`` is the (symmetric) mass matrix.
"""

from __future__ import annotations

import sympy as sp

from .kinematics import Kinematics, rigid_vec
from .modal_field import Field, vec_map

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


def _partials(expr, speeds):
    return [sp.diff(expr, u) for u in speeds]


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
        Vx, Vy, W = _partials(vx, speeds), _partials(vy, speeds), _partials(frame.omega, speeds)
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
        V = [vec_map(bm.v, lambda c, u=u: sp.diff(c, u)) for u in speeds]
        a_rem = kin.acceleration_remainder(bm.v, bm.frame.omega)
        active = [r for r in range(n) if not (V[r][0].is_zero() and V[r][1].is_zero())]
        for i, r in enumerate(active):
            for s in active[i:]:
                M[r][s] += consts.integrate(V[r][0], V[s][0]) + consts.integrate(V[r][1], V[s][1])
            rem[r] += consts.integrate(V[r][0], a_rem[0]) + consts.integrate(V[r][1], a_rem[1])
    for r in range(n):
        for s in range(r):
            M[r][s] = M[s][r]
    return InertiaForces(sp.Matrix(M), rem, speeds)


def field_partials(field: Field, speeds) -> list[Field]:
    """Partial derivatives of a field's coefficients with respect to each speed."""
    return [field.map(lambda c, u=u: sp.diff(c, u)) for u in speeds]
