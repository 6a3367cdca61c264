"""Eigenfunctions of the one-dimensional wave equation: bars in extension, shafts in torsion.

Axial deformation (``EA u'' = rho u_tt``) and uniform torsion (``GJ theta'' = rho I_p theta_tt``)
separate into ``Theta'' = -beta^2 Theta`` on ``[0, 1]``, whose eigenfunctions are sines and cosines:

* fixed at ``xi = 0``, free at ``xi = 1``: ``sqrt(2) sin(beta_k xi)``, ``beta_k = (2k - 1) pi / 2``;
* fixed at both ends: ``sqrt(2) sin(beta_k xi)``, ``beta_k = k pi``;
* free at both ends: ``sqrt(2) cos(beta_k xi)``, ``beta_k = k pi``, and the rigid mode ``1``.

The factor ``sqrt(2)`` gives the mass normalisation ``int_0^1 Theta_k Theta_l dxi = delta_kl``
shared by every eigenfunction family of this package, and the natural frequencies are
``p_k = (beta_k / L) (stiffness / inertia)^(1/2)`` (not eq. 8.7).
"""

from __future__ import annotations

import math

import numpy as np

from .base import check_positive
from .eigen import EigenFamily

__all__ = ["WaveFamily", "fixed_free_roots", "whole_wave_roots"]


def fixed_free_roots(n: int) -> np.ndarray:
    """``beta_k = (2k - 1) pi / 2``, ``k = 1..n``: one end fixed, the other free; shape ``(n,)``."""
    return (2.0 * np.arange(1, n + 1) - 1.0) * math.pi / 2.0


def whole_wave_roots(n: int) -> np.ndarray:
    """``beta_k = k pi``, ``k = 1..n``: both ends fixed, or both free; shape ``(n,)``."""
    return np.arange(1, n + 1) * math.pi


class WaveFamily(EigenFamily):
    """Base class of the families of :mod:`flexkane.modes.wave` (module docstring).

    Subclasses set ``_form`` (``"sin"`` or ``"cos"``) and implement :meth:`_compute_roots`.
    """

    _form = "sin"

    def _raw_coefficients(self, lam: np.ndarray) -> np.ndarray:
        zero = np.zeros_like(lam)
        amplitude = np.full_like(lam, math.sqrt(2.0))
        if self._form == "cos":
            return np.vstack([zero, zero, amplitude, zero])
        return np.vstack([zero, zero, zero, amplitude])

    def _ensure(self, n: int) -> None:
        # already mass-normalised; the fourth-order norm identity is not needed
        if self._lam.size < n:
            self._lam = self._compute_roots(n)
            self._coeffs = self._raw_coefficients(self._lam)

    def quadrature_order(self, n: int) -> int:
        return n + 30

    def _wave_frequencies(self, n: int, L, stiffness, inertia, names: tuple[str, str, str, str]) -> np.ndarray:
        """``p_k = (beta_k / L) (stiffness / inertia)^(1/2)`` [rad/s], shape ``(n,)``.

        ``names``: the argument names and descriptions (with units) of the stiffness and the
        inertia, for error messages.
        """
        beta = self.roots(n)
        L = check_positive(L, "L", "the length of the beam [m]")
        stiffness = check_positive(stiffness, names[0], names[1])
        inertia = check_positive(inertia, names[2], names[3])
        return beta / L * math.sqrt(stiffness / inertia)
