"""Perturbations of chains with closed loops: the dependent coordinates follow the independent ones.

A chain with loop joints keeps all its coordinates q (independent q_i and dependent q_d) in the state,
bound by the configuration constraints ``Phi(q, t) = 0`` (:mod:`flexkane.kane.constraints`). A
perturbation that keeps the loops closed satisfies ``Phi_q dq = 0``, i.e.

    dq_d = -Phi_d^-1 Phi_i dq_i,        dq = T dq_i,

with ``Phi_i``, ``Phi_d`` the columns of ``Phi_q = dPhi/dq`` of the independent and dependent
coordinates. The linear model of a closed chain is written in dq_i alone: ``K = -(df/dq) T`` and
``V = (dqdot/dq) T`` (rows of the independent coordinates), so that it has exactly as many degrees of
freedom as the mechanism (no spurious modes from the constraints).

A spatial chain whose loops make angular speeds of a spherical or free joint dependent has no
dependent coordinate of their own (they move Euler parameters, ``e' = 1/2 E(e) w``). Its
perturbations are first written in the rotation coordinates ``dq = T_r dx``, one per speed
(:mod:`flexkane.analysis.rotation_reduction`), where the loops read ``(Phi_q T_r) dx = 0``; a reduced
coordinate is dependent when its speed is (:func:`loop_columns`: ``ry_J``, ``rz_J`` when ``u_J_wy``,
``u_J_wz`` are), and the same map closes them, ``dx = T_c dx_i`` with
``T_c = closure_map(Phi_q T_r, ...)``. Together ``dq = T_r T_c dx_i`` and ``dx_i = (T_r^+)_i dq``
(the rows of the independent coordinates: ``(T_r^+)_i T_r T_c = (T_c)_i = I``), so that

    K = -(df/dq) T_r T_c,    W = (T_r^+)_i W_q,    V = (T_r^+)_i (V_q T_r T_c - T_r' T_c),

at rest ``T_r' = 0``.
"""

from __future__ import annotations

import numpy as np

from ..errors import ModelError

__all__ = ["closure_map", "loop_columns"]


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


def loop_columns(speeds: list[str], independent: list[str], dependent: list[str]) -> tuple[list[int], list[int]]:
    """Positions of the independent and dependent reduced coordinates of a spatial closed chain.

    Parameters
    ----------
    speeds : list of str
        Name of the speed of each reduced coordinate
        (:attr:`~flexkane.analysis.rotation_reduction.RotationReduction.speeds`).
    independent, dependent : list of str
        Names of the chain's independent speeds (in their order) and of its dependent ones.

    Returns
    -------
    independent, dependent : list of int
        The reduced coordinates of the independent speeds, in the order of ``independent``, and
        those of the dependent speeds.

    Raises
    ------
    ModelError
        If the speeds of the reduced coordinates are not the chain's speeds one to one.
    """
    position = {name: j for j, name in enumerate(speeds)}
    missing = [name for name in [*independent, *dependent] if name not in position]
    if missing or len(independent) + len(dependent) != len(speeds):
        raise ModelError("model", "one rotation or plain coordinate per independent or dependent speed",
                         f"speeds {', '.join(speeds)} for {', '.join([*independent, *dependent])}")
    return [position[name] for name in independent], sorted(position[name] for name in dependent)
