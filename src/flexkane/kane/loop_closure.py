"""Closure of the loop constraints ``Phi(q, t) = 0`` of a configuration, planar and spatial alike.

The unknowns are the coordinates of the dependent speeds (``EquationsOfMotion.dependent_coordinates``);
every other coordinate keeps the value given, bit for bit (a crank angle the user set stays set).
A dependent speed moves its coordinate at unit rate (``q' = u``: each dependent coordinate is an
unknown of its own), except an angular speed of a spherical or free joint, which moves the joint's
four Euler parameters, ``e' = 1/2 E(e) w``: those four then move on the unit sphere along the
rates' directions. So the coordinates move along

    dq = D(q) dx,   D[:, k] = e_{q_k}  or  de/dw_k = 1/2 E(e)[:, k],

one column per dependent speed. The unknowns x are the dependent coordinates themselves and, for
each dependent angular speed, its turn in the chart ``e(x) = (e_s + D_s x) / |e_s + D_s x|`` about
the start ``e_s`` (every orientation within half a turn of it); Powell's hybrid method
(``scipy.optimize.root``, ``hybr``) solves ``Phi(q(x)) = 0`` with the exact Jacobian
``Phi_q dq/dx`` (``Phi_q`` symbolic, of the unknowns only) to a step of 1e-14, a dependent
coordinate's move weighing :data:`PLAIN_WEIGHT` times a turn's in its step bound. Without Euler
parameters (planar chains) this is the root of the constraints in the dependent coordinates.
"""

from __future__ import annotations

import numpy as np
import sympy as sp

from ..errors import ModelError

__all__ = ["closure_unknowns", "project_coordinates"]

# largest residual of the closed constraints [m, rad, -]
CLOSURE_TOLERANCE = 1e-10
# with both dependent coordinates and turns among the unknowns, the weight of a coordinate's move
# against a turn's in the solver's step bound (initial bound 0.01 of the weighted start): the
# dependent coordinates stay near their guesses and the joints turn (a rocker angle given near one
# assembly branch of a spatial four-bar keeps it there)
PLAIN_WEIGHT = 1e3


def _euler_blocks(eom) -> list:
    """Index lists (into ``eom.q``) of the four Euler parameters of each spherical or free joint."""
    chain = eom.chain
    if chain.dimensions != 3:
        return []
    q = list(eom.q)
    blocks = []
    for joint in chain.joints:
        if joint.type in ("spherical", "free"):
            e = [c.q for c in chain.joint_coordinates(joint.name)][-4:]
            blocks.append([q.index(s) for s in e])
    return blocks


def _directions(eom) -> tuple:
    """The unknowns (indices into ``eom.q``, ascending) and the symbolic directions ``D`` of the
    dependent speeds (in the chain's order), shape (len(unknowns), number of dependent speeds)."""
    chain = eom.chain
    q = list(eom.q)
    blocks = _euler_blocks(eom)
    block_of = {i: b for b in blocks for i in b}
    coordinate_of = {c.u: c.q for c in chain.coordinates if c.u is not None}
    dep = [c.u for c in chain.coordinates if c.u in eom.dependent_speeds]     # in the chain's order
    unknowns: set = set()
    columns = []
    for u in dep:
        i = q.index(coordinate_of[u])
        if i in block_of:       # an angular speed of a spherical or free joint: its Euler parameters
            column = {j: sp.diff(chain.qdot[q[j]], u) for j in block_of[i]}
        else:
            column = {i: sp.Integer(1)}
        unknowns.update(column)
        columns.append(column)
    unknowns = sorted(unknowns)
    D = sp.Matrix([[col.get(j, sp.Integer(0)) for col in columns] for j in unknowns])
    return unknowns, D


def closure_unknowns(eom) -> list:
    """The coordinates the closure of the loops solves for (``eom.q`` order); the closure keeps the
    others as given.

    Parameters
    ----------
    eom : EquationsOfMotion

    Returns
    -------
    list of sympy.Symbol
        The dependent coordinates, and all four Euler parameters of a joint with a dependent angular
        speed; empty without loop constraints.
    """
    if not eom.dependent_speeds:
        return []
    return [eom.q[i] for i in _directions(eom)[0]]


def project_coordinates(eom, q: np.ndarray, p_values: dict, t: float = 0.0) -> np.ndarray:
    """Close the loop constraints: solve them for the unknowns (:func:`closure_unknowns`), the other
    coordinates kept exactly.

    Parameters
    ----------
    eom : EquationsOfMotion
    q : ndarray, shape (len(eom.q),)
        Coordinates [m, rad, -] (the unknowns' values are the starting guess).
    p_values : dict of sympy.Symbol to float
        Numeric constants (:func:`flexkane.kane.numeric.constant_values`).
    t : float
        Time [s].

    Returns
    -------
    ndarray, shape (len(eom.q),)
        The coordinates with the constraints closed to a residual below 1e-10, moved Euler
        parameters of unit norm.

    Raises
    ------
    ModelError
        If the constraints cannot be closed from ``q``.
    """
    from scipy.optimize import root

    start = np.array(q, dtype=float)
    if not eom.dependent_speeds:
        return start
    unknowns, D = _directions(eom)
    subs_const = {k: sp.Float(v) for k, v in p_values.items()}
    phi = sp.Matrix([e.xreplace(subs_const) for e in eom._phi])
    args = [eom.t] + list(eom.q)
    f = sp.lambdify(args, phi, "numpy")
    jac = sp.lambdify(args, phi.jacobian([eom.q[i] for i in unknowns]), "numpy")
    blocks = [[unknowns.index(i) for i in b] for b in _euler_blocks(eom) if b[0] in unknowns]
    in_block = {r for b in blocks for r in b}
    D_start = np.asarray(sp.lambdify(args, D, "numpy")(t, *start), dtype=float)
    # a dependent coordinate is its own unknown (row of its unit column); an angular speed turns a block
    plain = {k: int(np.flatnonzero(D_start[:, k])[0]) for k in range(D.shape[1])
             if not in_block.intersection(np.flatnonzero(D_start[:, k]))}
    turning = [k for k in range(D.shape[1]) if k not in plain]
    rows = np.array(unknowns)
    columns = np.array(list(plain.values()), dtype=int)
    q_cur = start.copy()

    def coordinates(x):
        y = start[rows] + D_start[:, turning] @ x[turning]
        y[columns] = x[list(plain)]
        for b in blocks:
            y[b] /= np.linalg.norm(y[b])
        q_cur[rows] = y
        return q_cur

    def residual(x):
        return np.asarray(f(t, *coordinates(x)), dtype=float).ravel()

    def jacobian(x):
        dq = np.zeros((len(unknowns), D.shape[1]))     # dq/dx
        dq[columns, list(plain)] = 1.0
        v = start[rows] + D_start[:, turning] @ x[turning]
        for b in blocks:    # d(v/|v|)/dv = (I - n n^T)/|v|
            size = np.linalg.norm(v[b])
            n = v[b] / size
            dq[np.ix_(b, turning)] = (np.eye(len(b)) - np.outer(n, n)) @ D_start[np.ix_(b, turning)] / size
        return np.asarray(jac(t, *coordinates(x)), dtype=float) @ dq

    x0 = np.zeros(D.shape[1])
    x0[list(plain)] = start[rows][columns]
    options = {}
    if turning and plain:   # steps measured with a coordinate's move weighing 1000 times a turn's
        options = {"diag": np.where(np.isin(np.arange(len(x0)), list(plain)), PLAIN_WEIGHT, 1.0), "factor": 0.01}
    sol = root(residual, x0, jac=jacobian, method="hybr", tol=1e-14, options=options)
    worst = float(np.abs(residual(sol.x)).max())
    if not worst <= CLOSURE_TOLERANCE:
        names = ", ".join(eom.q[i].name for i in unknowns)
        raise ModelError("initial", "initial coordinates from which the loop constraints can be closed "
                         f"(solving for {names})", f"residual {worst:.3g}")
    return coordinates(sol.x).copy()
