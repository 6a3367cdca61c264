"""Closure of the loop constraints ``Phi(q, t) = 0`` of a configuration, planar and spatial alike.

The unknowns are the coordinates of the dependent speeds (``EquationsOfMotion.dependent_coordinates``);
every other coordinate keeps the value given, bit for bit (a crank angle the user set stays set).
A dependent speed moves its coordinate at unit rate (``q' = u``: each dependent coordinate is an
unknown of its own), except an angular speed of a spherical or free joint, which moves the joint's
four Euler parameters, ``e' = 1/2 E(e) w``: those four are then unknowns on the unit sphere, moved
along the rates' directions and renormalized after each step. So the coordinates move along

    dq = D(q) dx,   D[:, k] = e_{q_k}  or  de/dw_k = 1/2 E(e)[:, k],

one column per dependent speed, and Newton's method solves ``Phi(q + D dx) = 0`` for ``dx`` with the
exact Jacobian ``A = Phi_q D`` (``Phi_q`` symbolic, of the unknowns only), each step halved while it
does not decrease the residual, until the residual can decrease no more (round-off).
"""

from __future__ import annotations

import numpy as np
import sympy as sp

from ..errors import ModelError

__all__ = ["closure_unknowns", "project_coordinates"]

# largest residual of the closed constraints [m, rad, -]
CLOSURE_TOLERANCE = 1e-10


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
    dependent speeds, shape (len(unknowns), number of dependent speeds)."""
    chain = eom.chain
    q = list(eom.q)
    blocks = _euler_blocks(eom)
    block_of = {i: b for b in blocks for i in b}
    dep = list(eom.dependent_speeds)
    coordinate_of = {c.u: c.q for c in chain.coordinates if c.u is not None}
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
    q = np.array(q, dtype=float)
    if not eom.dependent_speeds:
        return q
    unknowns, D = _directions(eom)
    subs_const = {k: sp.Float(v) for k, v in p_values.items()}
    phi = sp.Matrix([e.xreplace(subs_const) for e in eom._phi])
    args = [eom.t] + list(eom.q)
    f = sp.lambdify(args, phi, "numpy")
    jac = sp.lambdify(args, phi.jacobian([eom.q[i] for i in unknowns]) * D, "numpy", cse=True)
    moved_blocks = [b for b in _euler_blocks(eom) if b[0] in unknowns]

    def residual(x):
        return np.asarray(f(t, *x), dtype=float).ravel()

    def moved(x, step):
        y = x.copy()
        y[unknowns] = y[unknowns] + step
        for block in moved_blocks:
            y[block] /= np.linalg.norm(y[block])
        return y

    D_num = sp.lambdify(args, D, "numpy")
    r = residual(q)
    size = np.linalg.norm(r)
    for _ in range(100):
        if not size > 0:      # closed exactly (or not finite: judged below)
            break
        try:
            dx = np.linalg.solve(np.asarray(jac(t, *q), dtype=float), -r)
        except np.linalg.LinAlgError:
            break
        step = np.asarray(D_num(t, *q), dtype=float) @ dx
        for _halving in range(30):
            trial = moved(q, step)
            r_trial = residual(trial)
            size_trial = np.linalg.norm(r_trial)
            if size_trial < size:
                break
            step = step / 2
        else:
            break       # no decrease along the Newton direction: converged to round-off, or stuck
        q, r, size = trial, r_trial, size_trial
    worst = float(np.abs(r).max())
    if not worst <= CLOSURE_TOLERANCE:
        names = ", ".join(eom.q[i].name for i in unknowns)
        raise ModelError("initial", "initial coordinates from which the loop constraints can be closed "
                         f"(solving for {names})", f"residual {worst:.3g}")
    return q
