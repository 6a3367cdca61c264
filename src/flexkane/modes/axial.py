"""Shape functions of axial (longitudinal) deformation, ``u(x, t) = sum_k psi_k(x / L) s_k(t)``.

These are the eigenfunctions of the axial wave equation ``EA u'' = rho u_tt``:

* ``axial-fixed-free``: ``psi_k = sqrt(2) sin((2k - 1) pi xi / 2)``, ``beta_k = (2k - 1) pi / 2``;
* ``axial-fixed-fixed``: ``psi_k = sqrt(2) sin(k pi xi)``, ``beta_k = k pi``.

The factor ``sqrt(2)`` gives the mass normalisation ``int_0^1 psi_k psi_l dxi = delta_kl`` shared
by every eigenfunction family of this package. The natural frequencies are
``p_k = (beta_k / L) (EA / rho)^(1/2)`` (not eq. 8.7), and the stiffness integrals are
``int_0^L EA psi_k' psi_l' dx``.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from .base import check_positive
from .eigen import EigenFamily

__all__ = ["AxialFixedFree", "AxialFixedFixed"]


class _AxialFamily(EigenFamily):
    kind = "axial"

    def _raw_coefficients(self, lam: np.ndarray) -> np.ndarray:
        zero = np.zeros_like(lam)
        return np.vstack([zero, zero, zero, np.full_like(lam, math.sqrt(2.0))])

    def _ensure(self, n: int) -> None:
        # already mass-normalised; the fourth-order norm identity is not needed
        if self._lam.size < n:
            self._lam = self._compute_roots(n)
            self._coeffs = self._raw_coefficients(self._lam)

    def quadrature_order(self, n: int) -> int:
        return n + 30

    def frequencies(self, n: int, L: float, EA: Any, rho: float) -> np.ndarray:
        """Natural circular frequencies of axial vibration ``p_k = (beta_k / L) (EA / rho)^(1/2)``.

        Parameters
        ----------
        n : int
            Number of modes.
        L : float
            Length of the bar [m].
        EA : float
            Axial rigidity [N] (in the place of ``EI`` of the transverse families).
        rho : float
            Mass per unit length [kg/m].

        Returns
        -------
        numpy.ndarray
            ``p_k`` [rad/s], shape ``(n,)``.
        """
        beta = self.roots(n)
        L = check_positive(L, "L", "the length of the beam [m]")
        EA = check_positive(EA, "EA", "the axial rigidity [N]")
        rho = check_positive(rho, "rho", "the mass per unit length [kg/m]")
        return beta / L * math.sqrt(EA / rho)


class AxialFixedFree(_AxialFamily):
    """Axial modes of a bar fixed at ``xi = 0`` and free at ``xi = 1``."""

    name = "axial-fixed-free"
    boundary = "fixed-free"

    def _compute_roots(self, n: int) -> np.ndarray:
        return (2.0 * np.arange(1, n + 1) - 1.0) * math.pi / 2.0


class AxialFixedFixed(_AxialFamily):
    """Axial modes of a bar fixed at both ends."""

    name = "axial-fixed-fixed"
    boundary = "fixed-fixed"

    def _compute_roots(self, n: int) -> np.ndarray:
        return np.arange(1, n + 1) * math.pi
