"""Perturbations of chains with closed loops: the dependent coordinates follow the independent ones.

A chain with loop joints keeps all its coordinates q (independent q_i and dependent q_d) in the state,
bound by the configuration constraints ``Phi(q, t) = 0`` (:mod:`flexkane.kane.constraints`). A
perturbation that keeps the loops closed satisfies ``Phi_q dq = 0``, i.e.

    dq_d = -Phi_d^-1 Phi_i dq_i,        dq = T dq_i,

with ``Phi_i``, ``Phi_d`` the columns of ``Phi_q = dPhi/dq`` of the independent and dependent
coordinates. The linear model of a closed chain is written in dq_i alone: ``K = -(df/dq) T`` and
``V = (dqdot/dq) T`` (rows of the independent coordinates), so that it has exactly as many degrees of
freedom as the mechanism (no spurious modes from the constraints).
"""

from __future__ import annotations

import numpy as np

from ..errors import ModelError

__all__ = ["closure_map"]


def closure_map(Phi_q: np.ndarray, independent: list[int], dependent: list[int]) -> np.ndarray:
    """The matrix T of ``dq = T dq_i`` (module docstring).

    Parameters
    ----------
    Phi_q : numpy.ndarray
        Constraint Jacobian at the operating point, shape (m, n_q).
    independent, dependent : list of int
        Columns of the independent (n_i of them) and dependent (m) coordinates.

    Returns
    -------
    numpy.ndarray
        Shape (n_q, n_i); the rows of the independent coordinates form the identity.

    Raises
    ------
    ModelError
        If the loops cannot be closed by the dependent coordinates there (a singular configuration).
    """
    n_q = Phi_q.shape[1]
    T = np.zeros((n_q, len(independent)))
    T[independent, np.arange(len(independent))] = 1.0
    if dependent:
        Phi_d = Phi_q[:, dependent]
        if np.linalg.matrix_rank(Phi_d) < len(dependent):
            raise ModelError("constraints", "a configuration where the dependent coordinates close the loops "
                             "(non-singular constraint Jacobian)", "a singular configuration")
        T[dependent] = -np.linalg.solve(Phi_d, Phi_q[:, independent])
    return T
