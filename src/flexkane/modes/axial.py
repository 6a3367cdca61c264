"""Shape functions of axial (longitudinal) deformation, ``u(x, t) = sum_k psi_k(x / L) s_k(t)``.

These are the eigenfunctions of the axial wave equation ``EA u'' = rho u_tt``:

* ``axial-fixed-free``: ``psi_k = sqrt(2) sin((2k - 1) pi xi / 2)``, ``beta_k = (2k - 1) pi / 2``;
* ``axial-fixed-fixed``: ``psi_k = sqrt(2) sin(k pi xi)``, ``beta_k = k pi``

(:mod:`flexkane.modes.wave`, mass-normalised). The natural frequencies are
``p_k = (beta_k / L) (EA / rho)^(1/2)`` (not eq. 8.7), and the stiffness integrals are
``int_0^L EA psi_k' psi_l' dx``.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .wave import WaveFamily, fixed_free_roots, whole_wave_roots

__all__ = ["AxialFixedFree", "AxialFixedFixed"]


class _AxialFamily(WaveFamily):
    kind = "axial"

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
        return self._wave_frequencies(n, L, EA, rho, ("EA", "the axial rigidity [N]",
                                                     "rho", "the mass per unit length [kg/m]"))


class AxialFixedFree(_AxialFamily):
    """Axial modes of a bar fixed at ``xi = 0`` and free at ``xi = 1``."""

    name = "axial-fixed-free"
    boundary = "fixed-free"

    def _compute_roots(self, n: int) -> np.ndarray:
        return fixed_free_roots(n)


class AxialFixedFixed(_AxialFamily):
    """Axial modes of a bar fixed at both ends."""

    name = "axial-fixed-fixed"
    boundary = "fixed-fixed"

    def _compute_roots(self, n: int) -> np.ndarray:
        return whole_wave_roots(n)
