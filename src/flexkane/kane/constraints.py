"""Loop-closure constraints and Kane's method with dependent generalized speeds.

A loop joint adds configuration constraints ``Phi(q, t) = 0``; differentiating them with the kinematic
equations gives the velocity constraints ``A(q, t) u + a(q, t) = 0``, linear in the speeds. With as
many dependent speeds ``u_d`` as constraints, ``u_d = -A_d^-1 (A_i u_i + a)``: the remaining speeds
``u_i`` are independent, and Kane's equations (8.36) are formed with the partial velocities that take
the constraints into account (Kane and Levinson's nonholonomic partial velocities):

    u = P u_i + p,   u' = P u_i' + e,   P^T M P u_i' = P^T (f - M e)

where ``P`` stacks the identity (independent rows) and ``C = -A_d^-1 A_i`` (dependent rows), and
``e = -A_d^-1 c`` with ``c`` the part of the acceleration constraint ``A u' + c = 0`` free of u'.
All coordinates stay in the state and are integrated with the kinematic equations, in which the
dependent speeds are replaced by their expressions, so the constraints hold to the integrator's
tolerance; a stabilization rate ``beta`` replaces ``a`` by ``a + beta Phi`` (``Phi' = -beta Phi``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import sympy as sp

from ..errors import ModelError
from .kinematics import Kinematics, rot

__all__ = ["ConstraintSet", "loop_constraints", "choose_dependent"]


@dataclass
class ConstraintSet:
    """Configuration constraints of a chain's loop joints.

    Attributes
    ----------
    names : list of str
        ``<constraint>_<k>`` for each scalar constraint.
    phi : list of sympy.Expr
        Configuration constraints Phi(q, t) [m or rad].
    rates : list of float
        Stabilization rate of each [1/s].
    dependent : list of str or None
        Speeds named as dependent in the model, in order (None where to be chosen).
    """

    names: list
    phi: list
    rates: list
    dependent: list


def loop_constraints(kin: Kinematics) -> ConstraintSet:
    """Configuration constraints of every loop joint of the model."""
    names, phi, rates, dependent = [], [], [], []
    for con in kin.chain.model.constraints.values():
        path = f"constraints.{con.name}"
        if getattr(kin, "dimensions", 2) == 3:   # spherical, point_on_line, weld
            from .spatial_constraints import closure_equations

            eqs = closure_equations(kin, con, path)
        elif con.type == "revolute":
            a, b = kin.end_frame(con, "a", path), kin.end_frame(con, "b", path)
            eqs = [b.r[0] - a.r[0], b.r[1] - a.r[1]]
        else:
            a, b = kin.end_frame(con, "a", path), kin.end_frame(con, "b", path)
            axis = kin.value(f"{path}.axis", con.axis, f"alpha_{con.name}")
            angle = kin.value(f"{path}.angle", con.angle, f"theta_{con.name}")
            normal = rot(a.theta + axis, (sp.Integer(0), sp.Integer(1)))
            eqs = [normal[0] * (b.r[0] - a.r[0]) + normal[1] * (b.r[1] - a.r[1]), b.theta - a.theta - angle]
        for k, eq in enumerate(eqs):
            names.append(f"{con.name}_{k + 1}")
            phi.append(eq)
            rates.append(kin.value(f"{path}.stabilization", con.stabilization, f"beta_{con.name}")
                         if isinstance(con.stabilization, str) else float(con.stabilization))
        given = list(con.dependent or [])
        if given and len(given) != len(eqs):
            raise ModelError(f"{path}.dependent", f"{len(eqs)} speed names (one per scalar constraint)", given)
        dependent += given if given else [None] * len(eqs)
    return ConstraintSet(names, phi, rates, dependent)


def choose_dependent(A: np.ndarray, speeds: list, preferred: list[bool], given: list) -> list[int]:
    """Indices of the dependent speeds: the given ones, then by column pivoting on ``A``.

    Parameters
    ----------
    A : ndarray, shape (m, n)
        Velocity-constraint matrix at the initial configuration.
    speeds : list of sympy.Symbol
        The free speeds (columns of A).
    preferred : list of bool
        Columns that may be chosen automatically (joint speeds, not modal ones).
    given : list of str or None
        Names given in the model, or None.
    """
    names = [u.name for u in speeds]
    chosen = []
    for name in given:
        if name is None:
            continue
        if name not in names:
            raise ModelError("constraints.dependent", f"names of free generalized speeds ({', '.join(names)})", name)
        chosen.append(names.index(name))
    m = A.shape[0]
    work = A.copy()
    if chosen:
        # remove the directions spanned by the given columns (which must be independent)
        singular = np.linalg.svd(work[:, chosen], compute_uv=False)
        if singular.min() <= 1e-12 * max(1.0, np.abs(A).max()):
            raise ModelError("constraints.dependent", "dependent speeds whose columns of the constraint matrix "
                             "are independent at the initial configuration (the loops can be solved for them)",
                             [names[j] for j in chosen])
        Q, _ = np.linalg.qr(work[:, chosen])
        work = work - Q @ (Q.T @ work)
    candidates = [j for j in range(len(speeds)) if preferred[j] and j not in chosen]
    while len(chosen) < m:
        norms = [np.linalg.norm(work[:, j]) for j in candidates]
        if not candidates or max(norms) < 1e-12 * max(1.0, np.abs(A).max()):
            raise ModelError("constraints", "independent loop constraints (the constraint matrix at the initial "
                             "configuration has lower rank than the number of constraints)",
                             f"{m} constraints, rank {len(chosen)}")
        j = candidates[int(np.argmax(norms))]
        chosen.append(j)
        candidates.remove(j)
        v = work[:, j] / np.linalg.norm(work[:, j])
        work = work - np.outer(v, v @ work)
    return chosen
