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

The initial state is closed as a planar one's (:func:`flexkane.kane.loop_closure.project_coordinates`;
a dependent angular speed of a spherical or free joint moves its joint's Euler parameters).
"""

from __future__ import annotations

from itertools import combinations

import sympy as sp

from ..errors import ModelError
from .spatial_frame import dot
from .spatial_joints import direction, orientation, plane_axes

__all__ = ["closure_equations", "named_det_adjugate"]


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
        eqs = d
    elif con.type == "point_on_line":
        n = direction(kin.symbols, f"{path}.axis", con.axis, f"n_{con.name}")
        e1, e2 = plane_axes(n, f"{path}.axis")
        local = a.rotation.inverse_apply(d)
        eqs = [dot(e1, local), dot(e2, local)]
    elif con.type == "weld":
        target = a.rotation * orientation(kin.symbols, f"{path}.orientation", con.orientation, f"O_{con.name}")
        eqs = d + _vect(target.matrix.T * b.rotation.matrix)
    else:
        raise ModelError(f"{path}.type", "spherical, point_on_line or weld", con.type)
    # named: their rates and partial derivatives (the constraint matrix) stay small, whatever the
    # frames at the ends (a beam section turned by its slopes and twist)
    return [kin.chain.name(e, f"Phi{k + 1}_{con.name}") for k, e in enumerate(eqs)]


def named_det_adjugate(A: sp.Matrix, chain, label: str = "loops") -> tuple:
    """Determinant and adjugate of a square matrix, every minor a named intermediate.

    Each minor is expanded along its last row from the minors of one size less (Laplace, with the
    minors memoized by their set of columns), so the work grows as ``m^2 2^m`` named sums of at most
    m products however large the entries, where Berkowitz's adjugate of a 6 x 6 matrix of
    intermediates (a weld) multiplies them out. No pivot: the determinant is the only divisor.

    Parameters
    ----------
    A : sympy.Matrix, shape (m, m)
    chain : Chain
        Whose registry names the minors (``minor_<label>``, ``det_<label>``).
    label : str

    Returns
    -------
    det : sympy.Expr
    adj : sympy.Matrix, shape (m, m)
        ``adj * A = det * I``.
    """
    m = A.shape[0]

    def last_minors(rows):
        """det of the rows ``rows`` (in order) and each set of len(rows) columns."""
        level = {(): sp.Integer(1)}
        for k, i in enumerate(rows):
            nxt = {}
            for cols in combinations(range(m), k + 1):
                terms = [(-1) ** (k + pos) * A[i, j] * level[cols[:pos] + cols[pos + 1:]]
                         for pos, j in enumerate(cols) if A[i, j] != 0]
                nxt[cols] = chain.name(sp.Add(*terms), f"minor_{label}")
            level = nxt
        return level

    cofactor = sp.zeros(m, m)
    for i in range(m):
        minors = last_minors([r for r in range(m) if r != i])
        for j in range(m):
            cofactor[i, j] = (-1) ** (i + j) * minors[tuple(c for c in range(m) if c != j)]
    det = chain.name(sp.Add(*[A[0, j] * cofactor[0, j] for j in range(m)]), f"det_{label}")
    return det, cofactor.T
