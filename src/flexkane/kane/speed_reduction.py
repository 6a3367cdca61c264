"""Kane's equations in independent speeds: the reduction every ideal speed constraint shares.

Closed loops (:mod:`flexkane.kane.loop_reduction`) and drivers whose laws read the state
(:mod:`flexkane.kane.driver_laws`) both make some speeds dependent, ``u = P u_i + p``; the equations in the
independent speeds follow from the partial velocities ``P`` alone. The module knows no chain, so both
reductions import it without an import circle.
"""

from __future__ import annotations

import sympy as sp

__all__ = ["dependent_speed_reduction"]


def dependent_speed_reduction(M: sp.Matrix, f: sp.Matrix, P: sp.Matrix, e: sp.Matrix) -> tuple:
    """Kane's equations in the independent speeds: ``P^T M P u_i' = P^T (f - M e)``.

    With ``u = P u_i + p`` and ``u' = P u_i' + e``, the columns of ``P`` are the partial velocities
    of the independent speeds in the speeds of ``M u' = f``; the forces that keep the dependent speeds
    dependent do no work in them (ideal constraints: closed loops, drivers of the state).

    Parameters
    ----------
    M : sympy.Matrix, shape (n, n)
    f : sympy.Matrix, shape (n, 1)
    P : sympy.Matrix, shape (n, ni)
    e : sympy.Matrix, shape (n, 1)

    Returns
    -------
    (sympy.Matrix, sympy.Matrix)
        The mass matrix (ni, ni) and the forcing (ni, 1).
    """
    PT = P.T
    return PT * M * P, PT * (f - M * e)
