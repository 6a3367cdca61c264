"""Free vibration of a beam on a fixed base (eqs. 8.3, 8.5) and Rayleigh-Ritz statics.

With mass-normalised eigenfunctions (eq. 8.8) the modal coordinates of eq. 8.5,
``q_i = alpha_i cos p_i t + beta_i sin p_i t``, follow from the initial deflection ``y0`` and
velocity ``v0`` by orthogonality:

    alpha_i = int_0^1 y0(xi) Phi_i(xi) dxi,      beta_i = int_0^1 v0(xi) Phi_i(xi) dxi / p_i.

(They are computed as the least-squares projection ``G^-1 int y0 Phi``, which is the same for
orthonormal modes and stays right for modes with typed roots, whose Gram matrix ``G`` is only
nearly the identity.)

Rigid-body modes (``family.rigid_modes``, zero frequency) move as ``q = alpha + beta t``.
"""

from __future__ import annotations

import math
from typing import Any, Callable

import numpy as np
import scipy.linalg
from scipy.integrate import quad_vec

from ..errors import ModelError
from .base import ShapeFamily, check_mode_count, check_positive
from .integrals import gauss_legendre, mass_integrals, quadrature_order, stiffness_integrals

__all__ = ["FreeVibration", "tip_load_shape", "static_tip_load_coordinates",
           "rayleigh_ritz_frequencies"]

#: Relative accuracy of the projections of the initial shapes on the modes.
_PROJECTION_TOLERANCE = 1e-10


def _project(integrand: Callable[[np.ndarray], np.ndarray], order: int) -> np.ndarray:
    """``int_0^1 integrand(xi) dxi`` for a vectorised integrand of shape ``(..., N)``.

    Gauss-Legendre of orders ``order`` and ``2 order`` when they agree (smooth initial shapes);
    otherwise adaptive Gauss-Kronrod (``scipy.integrate.quad_vec``), which copes with the kinks
    of, e.g., a plucked beam, where Gauss-Legendre converges only like ``order^-2``.
    """
    results = []
    for k in (order, 2 * order):
        xi, w = gauss_legendre(k)
        results.append(integrand(xi) @ w)
    scale = max(np.abs(results[1]).max(), np.finfo(float).tiny)
    if np.abs(results[1] - results[0]).max() <= _PROJECTION_TOLERANCE * scale:
        return results[1]
    breaks = np.linspace(0.0, 1.0, max(2, order // 8))[1:-1]
    value, error = quad_vec(lambda x: integrand(np.array([x]))[..., 0], 0.0, 1.0,
                            epsabs=_PROJECTION_TOLERANCE * scale, epsrel=_PROJECTION_TOLERANCE,
                            norm="max", limit=20000, points=breaks)
    if not np.all(np.isfinite(value)) or error > 1e3 * _PROJECTION_TOLERANCE * scale:
        raise ModelError("initial_deflection", "initial shapes integrable on 0 <= xi <= 1",
                         f"modal projections accurate only to {error:.2g}")
    return value


def tip_load_shape(L: float, EI: float, P: float) -> Callable[[np.ndarray], np.ndarray]:
    """Static deflection of a cantilever under a tip load, ``y = P x^2 (3 L - x) / (6 EI)``.

    Parameters
    ----------
    L : float
        Length [m].
    EI : float
        Flexural rigidity [N m^2].
    P : float
        Transverse tip load [N] (either sign).

    Returns
    -------
    callable
        ``y0(xi)`` [m] for ``xi = x / L``, vectorised.
    """
    L = check_positive(L, "L", "the length of the beam [m]")
    EI = check_positive(EI, "EI", "the flexural rigidity [N m^2]")
    P = float(P)
    if not math.isfinite(P):
        raise ModelError("P", "a finite tip load [N]", P)
    scale = P * L ** 3 / (6.0 * EI)
    return lambda xi: scale * np.asarray(xi, dtype=float) ** 2 * (3.0 - np.asarray(xi, dtype=float))


def _values(function: Callable[[np.ndarray], Any] | None, x: np.ndarray, path: str) -> np.ndarray:
    if function is None:
        return np.zeros_like(x)
    if not callable(function):
        raise ModelError(path, "a vectorised function of xi = x/L", function)
    values = np.broadcast_to(np.asarray(function(x), dtype=float), x.shape)
    if not np.all(np.isfinite(values)):
        raise ModelError(path, "a function finite on 0 <= xi <= 1", function)
    return values


class FreeVibration:
    """Free vibration ``y(x, t) = sum_i Phi_i(x/L) q_i(t)`` of a beam on a fixed base.

    Parameters
    ----------
    family : ShapeFamily
        An eigenfunction family without tip body (``clamped-free``, ``pinned-pinned``, ...).
    n : int
        Number of elastic modes kept.
    L : float
        Length of the beam [m].
    EI : float
        Flexural rigidity [N m^2].
    rho : float
        Mass per unit length [kg/m].
    initial_deflection : callable
        ``y0(xi)`` [m], vectorised over ``xi = x / L``.
    initial_velocity : callable or None
        ``v0(xi)`` [m/s]; ``None`` for a release from rest.

    Attributes
    ----------
    alpha, beta : numpy.ndarray
        Coefficients of eq. 8.5 [m] for the elastic modes, shape ``(n,)``.
    frequencies : numpy.ndarray
        ``p_i`` [rad/s] (eq. 8.7), shape ``(n,)``.
    rigid_alpha, rigid_beta : numpy.ndarray
        ``q = alpha + beta t`` of the rigid modes [m], [m/s], shape ``(len(family.rigid_modes),)``.
    """

    def __init__(self, family: ShapeFamily, n: int, L: float, EI: float, rho: float,
                 initial_deflection: Callable[[np.ndarray], Any],
                 initial_velocity: Callable[[np.ndarray], Any] | None):
        if family.roots(1) is None or family.kind != "transverse" \
                or family.name == "clamped-free-tip-mass":
            raise ModelError("family", "a transverse eigenfunction family without tip body",
                             family.name, hint="use static_tip_load_coordinates for Ritz families")
        self.family = family
        self.n = check_mode_count(n)
        self.L = check_positive(L, "L", "the length of the beam [m]")
        self.EI = check_positive(EI, "EI", "the flexural rigidity [N m^2]")
        self.rho = check_positive(rho, "rho", "the mass per unit length [kg/m]")
        self.frequencies = family.frequencies(self.n, self.L, self.EI, self.rho)

        def integrand(xi: np.ndarray) -> np.ndarray:
            """Rows ``Phi y0, Phi v0, Phi Phi^T`` at the abscissae ``xi``, shape (m, 2 + m, N)."""
            y0 = _values(initial_deflection, xi, "initial_deflection")
            v0 = _values(initial_velocity, xi, "initial_velocity")
            modes = np.vstack([family.rigid_phi(xi), family.phi(xi, self.n)])
            return modes[:, None, :] * np.vstack([y0, v0, modes])[None, :, :]

        projections = _project(integrand, quadrature_order(family, self.n))
        # G c = int y Phi: for mass-normalised modes G = I (eq. 8.8), and c = int y Phi_i;
        # the solve also serves modes with typed, hence slightly non-orthogonal, roots
        coefficients = np.linalg.solve(projections[:, 2:], projections[:, :2])
        r = len(family.rigid_modes)
        self.rigid_alpha, self.rigid_beta = coefficients[:r, 0], coefficients[:r, 1]
        self.alpha = coefficients[r:, 0]
        self.beta = coefficients[r:, 1] / self.frequencies

    @classmethod
    def from_tip_load(cls, family: ShapeFamily, n: int, L: float, EI: float, rho: float,
                      P: float) -> "FreeVibration":
        """A cantilever released from rest from its static shape under the tip load ``P`` [N]."""
        if family.boundary != "clamped-free" or family.name == "clamped-free-tip-mass":
            raise ModelError("family", "clamped-free for a tip-load release", family.name)
        return cls(family, n, L, EI, rho, tip_load_shape(L, EI, P), None)

    def deflection(self, x: Any, t: Any) -> np.ndarray:
        """Deflection ``y(x, t)`` [m] (eqs. 8.3, 8.5).

        Parameters
        ----------
        x : float or array_like
            Abscissae [m] in ``[0, L]``, shape ``(P,)``.
        t : float or array_like
            Times [s], shape ``(T,)``.

        Returns
        -------
        numpy.ndarray
            Shape ``(T, P)``.
        """
        return self._field(x, t, derivative=False)

    def velocity(self, x: Any, t: Any) -> np.ndarray:
        """Velocity ``dy/dt (x, t)`` [m/s], shape ``(T, P)``; arguments as :meth:`deflection`."""
        return self._field(x, t, derivative=True)

    def _field(self, x: Any, t: Any, derivative: bool) -> np.ndarray:
        xs = np.atleast_1d(np.asarray(x, dtype=float))
        if xs.ndim != 1 or np.any(xs < 0.0) or np.any(xs > self.L):
            raise ModelError("x", f"abscissae in [0, L] = [0, {self.L:g}] m", x)
        ts = np.atleast_1d(np.asarray(t, dtype=float))
        xi = xs / self.L
        pt = np.outer(ts, self.frequencies)                          # (T, n)
        if derivative:
            q = self.frequencies * (-self.alpha * np.sin(pt) + self.beta * np.cos(pt))
            q_rigid = np.broadcast_to(self.rigid_beta, (ts.size, self.rigid_beta.size))
        else:
            q = self.alpha * np.cos(pt) + self.beta * np.sin(pt)
            q_rigid = self.rigid_alpha + np.outer(ts, self.rigid_beta)
        return q @ self.family.phi(xi, self.n) + q_rigid @ self.family.rigid_phi(xi)


def static_tip_load_coordinates(family: ShapeFamily, n: int, L: float, EI: float,
                                P: float) -> np.ndarray:
    """Rayleigh-Ritz statics: solve ``H q = P Phi(L)`` for a transverse tip load ``P``.

    Parameters
    ----------
    family : ShapeFamily
        Shape functions admissible for a clamped root.
    n : int
        Number of functions.
    L : float
        Length [m].
    EI : float
        Flexural rigidity [N m^2].
    P : float
        Tip load [N].

    Returns
    -------
    numpy.ndarray
        Generalised coordinates ``q`` [m], shape ``(n,)``; the tip deflection is
        ``q @ family.phi(1.0, n)[:, 0]``.
    """
    H = stiffness_integrals(family, n, L, EI)
    tip = family.phi(np.ones(1), n)[:, 0]
    return scipy.linalg.solve(H, float(P) * tip, assume_a="sym")


def rayleigh_ritz_frequencies(family: ShapeFamily, n: int, L: float, EI: float,
                              rho: float) -> np.ndarray:
    """Natural frequencies from ``H v = p^2 G v`` (eqs. 8.22, 8.32), ascending.

    For any admissible family these are upper bounds of the exact frequencies of the beam whose
    boundary the family satisfies; for eigenfunctions they are eq. 8.7 again.

    Parameters
    ----------
    family : ShapeFamily
        Shape functions.
    n : int
        Number of functions.
    L : float
        Length [m].
    EI : float
        Flexural rigidity [N m^2].
    rho : float
        Mass per unit length [kg/m].

    Returns
    -------
    numpy.ndarray
        ``p`` [rad/s], shape ``(n,)``.
    """
    G = mass_integrals(family, n, L, rho).G
    H = stiffness_integrals(family, n, L, EI)
    values = scipy.linalg.eigh(H, G, eigvals_only=True)
    return np.sqrt(np.clip(values, 0.0, None))
