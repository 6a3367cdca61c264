"""Kane's equations of a chain with closed loops, reduced to its independent speeds (a value).

:func:`reduce_by_loops` takes the equations over the free speeds (drivers substituted) and returns
a :class:`LoopReduction`: everything the loop constraints decide (:mod:`flexkane.kane.constraints`
states the method). With the velocity constraints ``A u + a = 0`` and the acceleration constraints
``A u' + c = 0``, the dependent speeds ``u_d = -A_d^-1 (A_i u_i + a)`` are chosen at the initial
configuration (:func:`~flexkane.kane.constraints.choose_dependent`), and

    u = P u_i + p,   u' = P u_i' + e,   P^T M P u_i' = P^T (f - M e)

with ``P`` the identity on the independent rows and ``-A_d^-1 A_i`` on the dependent ones and
``e = -A_d^-1 c``. ``A_d^-1`` is the adjugate over the determinant: no symbolic pivot that could
vanish at some configuration. The constraint forces ``A_d^T lambda`` are the dependent rows of
``M u' - f``; a driver also works against them through its own column of the constraint matrix,
which corrects its effort.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np
import sympy as sp

from ..expressions import bounded_expand
from ..model.columns import Outputs, constraint_residual_units
from ..model.coordinates import speed_unit
from .chain import BEAM_ROLES
from .constraints import ConstraintSet, choose_dependent
from .speed_reduction import dependent_speed_reduction

__all__ = ["LoopReduction", "reduce_by_loops"]


@dataclass(frozen=True)
class LoopReduction:
    """What the loop constraints decide of Kane's equations.

    Attributes
    ----------
    mass_matrix : sympy.Matrix, shape (len(u), len(u))
        ``P^T M P``, the dependent speeds replaced by their expressions.
    forcing : sympy.Matrix, shape (len(u), 1)
        ``P^T (f - M e)``, likewise.
    qdot : sympy.Matrix, shape (nq, 1)
        The kinematic equations, dependent speeds replaced (every coordinate stays in the state).
    zdot : sympy.Matrix, shape (nz, 1)
        The controller states' rates, dependent speeds replaced.
    u : tuple of sympy.Symbol
        The independent speeds, in the order of the free speeds.
    dependent_speeds : dict of sympy.Symbol to sympy.Expr
        Each dependent speed -> its expression in q, the independent speeds and t.
    driver_efforts : dict of str to sympy.Expr
        Joint -> the generalized force its driver supplies [N m or N], corrected by the constraint
        forces, as expressions of q, the independent u and u', t.
    outputs : dict of str to sympy.Expr
        Every output: those given with the efforts corrected, ``effort_<joint>`` and
        ``power_nonconservative`` with the corrected efforts, ``constraint_<name>`` (Phi [m or
        rad]) and each dependent speed by its name.
    dependent_coordinates : tuple of sympy.Symbol
        The coordinates of the dependent speeds, which the constraints decide in the initial state.
    phi : tuple of sympy.Expr
        Configuration constraints Phi(q, t), drivers substituted, intermediates written out.
    constraint_set : ConstraintSet
        The loop joints' constraints as given (names, Phi, stabilization rates, named dependents),
        drivers not substituted.
    """

    mass_matrix: sp.Matrix
    forcing: sp.Matrix
    qdot: sp.Matrix
    zdot: sp.Matrix
    u: tuple
    dependent_speeds: dict
    driver_efforts: dict
    outputs: Outputs
    dependent_coordinates: tuple
    phi: tuple
    constraint_set: ConstraintSet


def reduce_by_loops(chain, constraints: ConstraintSet, mass_matrix: sp.Matrix, forcing: sp.Matrix, qdot: sp.Matrix,
                    zdot: sp.Matrix, u: list, q: list, driver_efforts: dict, outputs: Outputs,
                    sub: Callable, at: dict, power: Callable) -> LoopReduction:
    """Kane's equations in the independent speeds of a chain with loop joints (eq. 8.36 with the
    partial velocities of the dependent-speed reduction).

    The inputs are not modified. For a spatial chain, the loops' solution (``C_loops``, ``u_loops``,
    ``ud_loops`` and the adjugate's entries) is named in the chain's intermediates.

    Parameters
    ----------
    chain : Chain
    constraints : ConstraintSet
        The loop joints' constraints (:func:`~flexkane.kane.constraints.loop_constraints`).
    mass_matrix : sympy.Matrix, shape (len(u), len(u))
        M over the free speeds, drivers substituted.
    forcing : sympy.Matrix, shape (len(u), 1)
    qdot : sympy.Matrix, shape (len(q), 1)
    zdot : sympy.Matrix, shape (nz, 1)
    u : list of sympy.Symbol
        The free speeds (not prescribed by a driver).
    q : list of sympy.Symbol
        The state coordinates.
    driver_efforts : dict of str to sympy.Expr
        Joint -> its driver's generalized force without the constraint forces [N m or N].
    outputs : Outputs
        The outputs over the free speeds (:class:`~flexkane.model.columns.Outputs`).
    sub : callable
        Substitution of the drivers' laws (expression -> expression).
    at : dict of sympy.Symbol to float
        The initial configuration, where the dependent speeds are chosen: every constant of the
        constraints (those they name included), coordinate and speed, and t.
    power : callable
        Driver efforts (dict as ``driver_efforts``) -> power of the non-conservative forces with
        those efforts, drivers substituted [W].

    Returns
    -------
    LoopReduction
    """
    cons = constraints
    t = chain.t
    ud_free = [chain.ud[s] for s in u]
    phi = [sub(e) for e in cons.phi]
    g_raw = [chain.dt(e) for e in cons.phi]
    # Phi' = A u + a: g_raw is linear and homogeneous in all the speeds (drivers not yet
    # substituted), so A is its partial derivatives with respect to the free speeds and a the part
    # of the driven ones, whose speeds become the drivers' laws
    driven = [c_.u for c_ in chain.coordinates if c_.driver is not None]
    simplified = lambda e: (expanded if (expanded := bounded_expand(e, [*u, *q], t))  # noqa: E731
                            is not None else e)
    A = sp.Matrix([[simplified(sub(chain.partial(gi, s))) for s in u] for gi in g_raw])
    a = sp.Matrix([simplified(sub(sp.Add(*[chain.partial(gi, s) * s for s in driven]))) + rate * ph
                   for gi, ph, rate in zip(g_raw, phi, cons.rates)])
    gd = [sub(chain.dt(e, with_ud=True)) for e in g_raw]
    c = sp.Matrix([e.xreplace({ud: 0 for ud in ud_free}) for e in gd])
    # choose the dependent speeds at the initial configuration
    A_full = sub(chain.intermediates.expand(A))
    A0 = np.array(A_full.xreplace({k: sp.Float(v) for k, v in at.items()}).evalf(), dtype=float)
    roles = {c_.u: c_.role for c_ in chain.coordinates}
    preferred = [roles[s] not in BEAM_ROLES for s in u]
    dep = choose_dependent(A0, u, preferred, cons.dependent)
    ind = [j for j in range(len(u)) if j not in dep]
    Ad = A[:, dep]
    Ai = A[:, ind]
    # A_d^-1 as adjugate / determinant: no symbolic pivot that could vanish at some configuration
    spatial = chain.dimensions == 3    # the loops' solution, named: it enters every equation
    named = (lambda m, label: m.applyfunc(lambda x: chain.name(x, label))) if spatial \
        else (lambda m, label: m)  # noqa: E731
    if spatial:
        from .spatial_constraints import named_det_adjugate

        det, adj = named_det_adjugate(Ad, chain)
    else:
        det = sp.factor_terms(Ad.det(method="berkowitz"))
        adj = Ad.adjugate(method="berkowitz")
    solve = lambda rhs: (adj * rhs) / det  # noqa: E731
    X = named(solve(Ai), "C_loops")
    y = solve(a)
    ui = sp.Matrix([u[j] for j in ind])
    u_dep = named(-X * ui - y, "u_loops")
    dep_subs = {u[j]: u_dep[k] for k, j in enumerate(dep)}
    e_dep = named(-solve(c.xreplace(dep_subs)), "ud_loops")
    n, ni = len(u), len(ind)
    P = sp.zeros(n, ni)
    e = sp.zeros(n, 1)
    for k, j in enumerate(ind):
        P[j, k] = 1
    for k, j in enumerate(dep):
        P[j, :] = -X[k, :]
        e[j] = e_dep[k]
    # u' of the dependent speeds in terms of the independent ones (for outputs)
    udi = sp.Matrix([ud_free[j] for j in ind])
    ud_dep = -X * udi + e_dep
    ud_subs = {ud_free[j]: ud_dep[k] for k, j in enumerate(dep)}
    # constraint forces: the dependent rows of M u' - f are A_d^T lambda; drivers also work against
    # them, through their own columns of the constraint matrix
    residual = (mass_matrix * sp.Matrix(ud_free) - forcing)
    lam = (adj.T * sp.Matrix([residual[j] for j in dep])) / det
    efforts = {}
    for owner, effort in driver_efforts.items():
        coord = chain.of(owner)[0]
        column = sp.Matrix([sub(chain.partial(g, coord.u)) for g in g_raw])
        efforts[owner] = effort - (column.T * lam)[0]
    M_reduced, f_reduced = dependent_speed_reduction(mass_matrix, forcing, P, e)
    out = outputs.copy()     # each name once (flexkane.model.columns)
    for owner, effort in efforts.items():
        out.replace(f"effort_{owner}", effort)
    out.replace("power_nonconservative", power(efforts))
    out = out.map(lambda v: v.xreplace(ud_subs).xreplace(dep_subs))
    units = [unit for con in chain.model.constraints.values()
             for unit in constraint_residual_units(con, chain.dimensions)]
    for name, ph, unit in zip(cons.names, phi, units, strict=True):
        out.add(f"constraint_{name}", ph, unit, "constraint", f"residual {name} of a loop constraint")
    for s, expr in dep_subs.items():
        out.add(s.name, expr, speed_unit(roles[s]), "dependent_speed", f"the dependent speed {s.name}")
    return LoopReduction(
        mass_matrix=M_reduced.applyfunc(lambda x: x.xreplace(dep_subs)),
        forcing=f_reduced.applyfunc(lambda x: x.xreplace(dep_subs)),
        qdot=qdot.applyfunc(lambda x: x.xreplace(dep_subs)),
        zdot=zdot.applyfunc(lambda x: x.xreplace(dep_subs)),
        u=tuple(u[j] for j in ind),
        dependent_speeds=dep_subs,
        driver_efforts={k: v.xreplace(ud_subs).xreplace(dep_subs) for k, v in efforts.items()},
        outputs=out,
        # the constraints decide the dependent coordinates of the initial state
        dependent_coordinates=tuple(c_.q for c_ in chain.coordinates if c_.u in dep_subs),
        phi=tuple(sub(chain.intermediates.expand(ph)) for ph in phi),
        constraint_set=cons)
