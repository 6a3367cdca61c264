"""Operating points: equilibria of ``M(q) u' = f(q, u, t)`` at ``u = 0``.

An equilibrium is a configuration q0 with ``f(q0, 0, t0) = 0`` (so that ``u' = 0``),
``q' = qdot(q0, 0, t0) = 0`` and, for chains with closed loops, ``Phi(q0, t0) = 0``.
:func:`find_equilibrium` searches for one from a starting configuration by least squares on the
forcing and the constraints (``scipy.optimize.least_squares``, Levenberg-Marquardt, with
``-K = df/dq`` and ``Phi_q`` as Jacobian, which copes with the singular K of chains that have
rigid-body freedoms); :func:`check_equilibrium` measures how far a configuration is from one.

Whether a configuration is an equilibrium is decided on the generalized accelerations
``a = M^-1 f``: it is when ``|a| <= 1e-9 s`` with the scale [m/s^2 or rad/s^2]

    s = max(|a(q_start)|, a_loads, max_i sum_j |(M^-1 K)_ij q_j|),

where ``a_loads`` is the size of the accelerations the loads can cause (the caller's estimate, e.g. g)
and the last term the size of the elastic and spring forces at q0: the accelerations left are then
rounding errors of the forces that act. A body in free fall keeps ``|a| = g`` wherever it is put:
it has no equilibrium, and :class:`NoEquilibriumError` says so. Loop constraints must hold to
``1e-10 max(|q0|, 1)`` [m or rad].
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
import scipy.linalg
from scipy.optimize import least_squares

from ..errors import ModelError

__all__ = ["NoEquilibriumError", "EquilibriumCheck", "check_equilibrium", "find_equilibrium",
           "EQUILIBRIUM_RTOL"]

#: Relative size of the generalized accelerations left at an accepted equilibrium.
EQUILIBRIUM_RTOL = 1e-9
_CONSTRAINT_TOLERANCE = 1e-10


class NoEquilibriumError(ModelError):
    """The model has no equilibrium (or none was found) where one was asked for.

    Parameters
    ----------
    about : str
        The operating point asked for (``equilibrium``, ``rest``, ``spin``).
    message : str
        What was found and what to do, in words.
    """

    def __init__(self, about: str, message: str):
        super().__init__(f"--about {about}", "a model with an equilibrium", None, show_given=False)
        self.args = (message,)


@dataclass(frozen=True)
class EquilibriumCheck:
    """How far a configuration is from an equilibrium.

    Attributes
    ----------
    q : numpy.ndarray
        The configuration, shape (n,).
    accelerations : numpy.ndarray
        ``u' = M^-1 f(q, 0, t0)``, shape (n,) [m/s^2 or rad/s^2].
    rates : numpy.ndarray
        ``q' = qdot(q, 0, t0)``, shape (n,) [m/s or rad/s].
    tolerance : float
        Largest acceptable ``|u'|`` (module docstring).
    constraints : numpy.ndarray
        Loop-constraint residuals Phi(q), shape (c,) [m or rad] (empty for open chains).
    iterations : int
        Iterations of the search that found q (:func:`find_equilibrium`; 0 where none was made).
    """

    q: np.ndarray
    accelerations: np.ndarray
    rates: np.ndarray
    tolerance: float
    constraints: np.ndarray = field(default_factory=lambda: np.zeros(0))
    iterations: int = 0

    @property
    def residual(self) -> float:
        """``max |u'|`` [m/s^2 or rad/s^2]."""
        return float(np.max(np.abs(self.accelerations), initial=0.0))

    @property
    def ok(self) -> bool:
        """Whether the configuration is an equilibrium."""
        closed = float(np.max(np.abs(self.constraints), initial=0.0)) <= \
            _CONSTRAINT_TOLERANCE * max(float(np.max(np.abs(self.q), initial=0.0)), 1.0)
        return (self.residual <= self.tolerance and closed
                and float(np.max(np.abs(self.rates), initial=0.0)) <= self.tolerance)


Evaluate = Callable[[np.ndarray], np.ndarray]


def check_equilibrium(q: np.ndarray, *, forcing: Evaluate, stiffness: Evaluate, mass: Evaluate,
                      rates: Evaluate, constraints: Evaluate | None = None,
                      constraint_jacobian: Evaluate | None = None,
                      start_accelerations: float = 0.0, load_accelerations: float = 0.0) -> EquilibriumCheck:
    """Accelerations, rates and constraint residuals at ``q`` and the tolerance they are judged by.

    Parameters
    ----------
    q : numpy.ndarray
        Configuration, shape (n_q,).
    forcing, stiffness, mass, rates : callable
        ``f(q, 0, t0)`` (n,), ``-df/dq`` (n, n_q), ``M(q)`` (n, n) and ``qdot(q, 0, t0)`` (n_q,).
    constraints, constraint_jacobian : callable, optional
        ``Phi(q)`` (c,) and ``Phi_q`` (c, n_q) of closed loops (``n_q = n + c``).
    start_accelerations : float
        ``|u'|`` where a search started [m/s^2 or rad/s^2] (part of the scale).
    load_accelerations : float
        Size of the accelerations the loads can cause [m/s^2 or rad/s^2] (part of the scale).

    Returns
    -------
    EquilibriumCheck
    """
    q = np.asarray(q, dtype=float)
    M = mass(q)
    try:
        accel = scipy.linalg.solve(M, forcing(q), assume_a="sym") if M.size else np.zeros(0)
        spread = scipy.linalg.solve(M, stiffness(q), assume_a="sym") if M.size else np.zeros((0, 0))
    except (np.linalg.LinAlgError, ValueError):
        raise ModelError("model", "a mass matrix that is not singular at the operating point",
                         f"a singular M at q = {np.array2string(q, precision=4)}") from None
    elastic = float(np.max(np.abs(spread) @ np.abs(q), initial=0.0)) if spread.size else 0.0
    scale = max(start_accelerations, load_accelerations, elastic)
    phi = np.asarray(constraints(q), dtype=float) if constraints is not None else np.zeros(0)
    return EquilibriumCheck(q, accel, np.asarray(rates(q), dtype=float), EQUILIBRIUM_RTOL * scale, phi)


def find_equilibrium(q_start: np.ndarray, *, forcing: Evaluate, stiffness: Evaluate, mass: Evaluate,
                     rates: Evaluate, constraints: Evaluate | None = None,
                     constraint_jacobian: Evaluate | None = None,
                     load_accelerations: float = 0.0) -> EquilibriumCheck:
    """Search for an equilibrium near ``q_start`` (see the module docstring).

    Parameters
    ----------
    q_start : numpy.ndarray
        Starting configuration, shape (n_q,).
    forcing, stiffness, mass, rates, constraints, constraint_jacobian : callable
        As for :func:`check_equilibrium`.
    load_accelerations : float
        As for :func:`check_equilibrium`.

    Returns
    -------
    EquilibriumCheck
        Of the best configuration found; ``ok`` tells whether it is an equilibrium.
    """
    ev = {"forcing": forcing, "stiffness": stiffness, "mass": mass, "rates": rates,
          "constraints": constraints, "constraint_jacobian": constraint_jacobian,
          "load_accelerations": load_accelerations}
    q_start = np.asarray(q_start, dtype=float)
    start = check_equilibrium(q_start, **ev)
    if q_start.size == 0 or start.ok:
        return start
    weight = 1.0
    if constraints is not None:
        # forces [N] and loop gaps [m] in one least-squares problem: balance their Jacobians
        K, G = stiffness(q_start), constraint_jacobian(q_start)
        if np.abs(G).max() > 0 and np.abs(K).max() > 0:
            weight = float(np.abs(K).max() / np.abs(G).max())

    def residual(q):
        f = forcing(q)
        return np.concatenate([f, weight * constraints(q)]) if constraints is not None else f

    def jacobian(q):
        J = -stiffness(q)
        return np.vstack([J, weight * constraint_jacobian(q)]) if constraints is not None else J

    with np.errstate(all="ignore"):
        solution = least_squares(residual, q_start, jac=jacobian, method="lm",
                                 xtol=1e-15, ftol=1e-15, gtol=1e-15, max_nfev=200 * (q_start.size + 1))
    q = solution.x if np.all(np.isfinite(solution.x)) else q_start
    found = check_equilibrium(q, **ev, start_accelerations=start.residual)
    found = dataclasses.replace(found, iterations=int(solution.njev or solution.nfev))
    return found if found.ok or found.residual <= start.residual else start
