"""Loop-closure constraints of spatial chains, and the closure of their initial state.

A spatial loop constraint joins an end a and an end b (a body's point, a beam's station or a ground
position; :meth:`~flexkane.kane.spatial_kinematics.SpatialKinematics.end_frame`), whose frames have
the positions ``r_a, r_b`` (N) and the orientations ``R_a, R_b`` in N:

================  ==========================================================  ===========
type              configuration constraints ``Phi(q) = 0``                    scalar ones
================  ==========================================================  ===========
spherical         ``r_b - r_a`` (components in N): coincident points           3
point_on_line     ``e_k . R_a^T (r_b - r_a)``, k = 1, 2: point b on the line    2
                  through point a along ``axis`` (frame a); ``e_1, e_2`` span
                  the plane normal to the axis (as a planar joint's, so for
                  the axis z they are x and y)
weld              ``r_b - r_a`` and ``vect(E)``, ``E = O^T R_a^T R_b``:         6
                  frame b at frame a turned by ``orientation`` (O); ``vect``
                  of a small turn ``I + [d x]`` is ``d``
================  ==========================================================  ===========

They become velocity constraints linear in the speeds and are eliminated by the dependent-speed
reduction of :mod:`flexkane.kane.constraints` (the same rule chooses the dependent speeds; a
drift is driven back by the constraint's ``stabilization`` rate, as in the plane).

A dependent speed of a spherical or free joint moves Euler parameters (``e' = 1/2 E(e) w``), not a
coordinate of its own; so the initial state is closed (:func:`project_coordinates`) by Newton's
method along the directions the dependent speeds move the coordinates, ``dq = K_d(q) dx`` with
``K_d = dq'/du_d``, whose constraint Jacobian is the velocity constraints' ``A_d``; each step
renormalizes the Euler parameters.
"""

from __future__ import annotations

import numpy as np
import sympy as sp

from ..errors import ModelError
from .spatial_frame import dot
from .spatial_joints import direction, orientation, plane_axes

__all__ = ["closure_equations", "needs_turning_projection", "project_coordinates"]


def _vect(E: sp.Matrix) -> list:
    """The axial vector of the skew part of a 3x3 matrix, ``d`` for ``E = I + [d x]`` [-]."""
    half = sp.Rational(1, 2)
    return [half * (E[2, 1] - E[1, 2]), half * (E[0, 2] - E[2, 0]), half * (E[1, 0] - E[0, 1])]


def closure_equations(kin, con, path: str) -> list:
    """The configuration constraints ``Phi`` of one spatial loop constraint (module docstring).

    Parameters
    ----------
    kin : SpatialKinematics
    con : LoopConstraint
    path : str
        Its key path (``constraints.<name>``).

    Returns
    -------
    list of sympy.Expr
        ``Phi`` [m, and - for a weld's orientation], 3, 2 or 6 of them.
    """
    a, b = kin.end_frame(con, "a", path), kin.end_frame(con, "b", path)
    d = [y - x for x, y in zip(a.r, b.r)]
    if con.type == "spherical":
        return d
    if con.type == "point_on_line":
        n = direction(kin.symbols, f"{path}.axis", con.axis, f"n_{con.name}")
        e1, e2 = plane_axes(n, f"{path}.axis")
        local = a.rotation.inverse_apply(d)
        return [dot(e1, local), dot(e2, local)]
    if con.type == "weld":
        target = a.rotation * orientation(kin.symbols, f"{path}.orientation", con.orientation, f"O_{con.name}")
        return d + _vect(target.matrix.T * b.rotation.matrix)
    raise ModelError(f"{path}.type", "spherical, point_on_line or weld", con.type)


def needs_turning_projection(eom) -> bool:
    """Whether a dependent speed of ``eom`` moves other than one coordinate at unit rate (a spherical
    or free joint's), so that the initial state is closed by :func:`project_coordinates`."""
    chain = eom.chain
    qdot = chain.qdot
    for coord in chain.coordinates:
        if coord.u in eom.dependent_speeds and (coord.q not in qdot or qdot[coord.q] != coord.u):
            return True
    return False


def _euler_blocks(chain, q: list) -> list:
    """Index lists (into ``q``) of the four Euler parameters of each spherical or free joint."""
    blocks = []
    for joint in chain.joints:
        if joint.type in ("spherical", "free"):
            e = [c.q for c in chain.of(joint.name)][-4:]
            blocks.append([q.index(s) for s in e])
    return blocks


def project_coordinates(eom, q: np.ndarray, p_values: dict, t: float = 0.0) -> np.ndarray:
    """Close the loop constraints by moving the coordinates along the dependent speeds' directions.

    Parameters
    ----------
    eom : EquationsOfMotion
    q : ndarray, shape (len(eom.q),)
        Coordinates [m, rad, -] (the starting guess).
    p_values : dict of sympy.Symbol to float
        Numeric constants (:func:`flexkane.kane.numeric.constant_values`).
    t : float
        Time [s].

    Returns
    -------
    ndarray, shape (len(eom.q),)
        The coordinates with the constraints closed to a residual below 1e-10, Euler parameters
        of unit norm.

    Raises
    ------
    ModelError
        If the constraints cannot be closed from ``q``.
    """
    chain = eom.chain
    dep = list(eom.dependent_speeds)
    subs_const = {k: sp.Float(v) for k, v in p_values.items()}
    phi = sp.Matrix([e.xreplace(subs_const) for e in eom._phi])
    qdot = sp.Matrix([chain.qdot[s].xreplace(eom.substitutions) for s in eom.q])
    directions = qdot.jacobian(dep).xreplace(subs_const)     # K_d: q' is linear in the speeds
    args = [eom.t] + list(eom.q)
    f = sp.lambdify(args, phi, "numpy")
    jac = sp.lambdify(args, phi.jacobian(list(eom.q)) * directions, "numpy")
    move = sp.lambdify(args, directions, "numpy")
    blocks = _euler_blocks(chain, list(eom.q))
    q = np.array(q, dtype=float)

    def residual(x):
        return np.asarray(f(t, *x), dtype=float).ravel()

    r = residual(q)
    for _ in range(50):
        if np.abs(r).max() <= 1e-13:
            break
        A = np.asarray(jac(t, *q), dtype=float)
        try:
            step = np.linalg.solve(A, -r)
        except np.linalg.LinAlgError:
            break
        trial = q + np.asarray(move(t, *q), dtype=float) @ step
        for block in blocks:
            trial[block] /= np.linalg.norm(trial[block])
        r_trial = residual(trial)
        if not np.all(np.isfinite(r_trial)):
            break
        q, r = trial, r_trial
    worst = float(np.abs(r).max())
    if not worst <= 1e-10:
        raise ModelError("initial", "initial coordinates from which the loop constraints can be closed "
                         f"(moving along the dependent speeds {', '.join(u.name for u in dep)})",
                         f"residual {worst:.3g}")
    return q
