"""Shape functions of uniform torsion, ``theta(x, t) = sum_k Theta_k(x / L) r_k(t)`` [rad].

These are the eigenfunctions of the torsion of a uniform shaft, ``GJ theta'' = rho I_p theta_tt``
(``GJ`` torsional rigidity [N m^2], ``rho I_p`` polar mass moment of inertia of the section per
unit length [kg m]), a wave equation (:mod:`flexkane.modes.wave`):

* ``torsion-clamped-free``: ``Theta_k = sqrt(2) sin((2k - 1) pi xi / 2)``, ``beta_k = (2k - 1) pi / 2``;
* ``torsion-clamped-clamped``: ``Theta_k = sqrt(2) sin(k pi xi)``, ``beta_k = k pi``;
* ``torsion-free-free``: ``Theta_k = sqrt(2) cos(k pi xi)``, ``beta_k = k pi``; the rigid rotation
  ``Theta_0 = 1`` is in ``rigid_modes``.

A clamped end holds the twist only (``Theta = 0``), so the families' boundaries are written with
``fixed``. They are normalised as the bending families (``int_0^1 Theta_k Theta_l dxi =
delta_kl``), their natural frequencies are ``p_k = (beta_k / L) (GJ / (rho I_p))^(1/2)`` and
their stiffness integrals ``int_0^L GJ Theta_k' Theta_l' dx``.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .base import RigidMode
from .wave import WaveFamily, fixed_free_roots, whole_wave_roots

__all__ = ["TorsionClampedFree", "TorsionClampedClamped", "TorsionFreeFree"]


class _TorsionFamily(WaveFamily):
    kind = "torsion"

    def frequencies(self, n: int, L: float, GJ: Any, rho_Ip: Any) -> np.ndarray:
        """Natural circular frequencies of torsion ``p_k = (beta_k / L) (GJ / (rho I_p))^(1/2)``.

        Parameters
        ----------
        n : int
            Number of modes.
        L : float
            Length of the shaft [m].
        GJ : float
            Torsional rigidity [N m^2] (in the place of ``EI`` of the transverse families).
        rho_Ip : float
            Polar mass moment of inertia of the section per unit length [kg m] (in the place of
            ``rho``).

        Returns
        -------
        numpy.ndarray
            ``p_k`` [rad/s], shape ``(n,)``.
        """
        return self._wave_frequencies(n, L, GJ, rho_Ip, (
            "GJ", "the torsional rigidity [N m^2]",
            "rho_Ip", "the polar mass moment of inertia of the section per unit length [kg m]"))


class TorsionClampedFree(_TorsionFamily):
    """Torsion modes of a shaft clamped at ``xi = 0`` and free at ``xi = 1``."""

    name = "torsion-clamped-free"
    boundary = "fixed-free"

    def _compute_roots(self, n: int) -> np.ndarray:
        return fixed_free_roots(n)


class TorsionClampedClamped(_TorsionFamily):
    """Torsion modes of a shaft clamped at both ends."""

    name = "torsion-clamped-clamped"
    boundary = "fixed-fixed"

    def _compute_roots(self, n: int) -> np.ndarray:
        return whole_wave_roots(n)


class TorsionFreeFree(_TorsionFamily):
    """Elastic torsion modes of a shaft free at both ends; the rigid rotation is a rigid mode."""

    name = "torsion-free-free"
    boundary = "free-free"
    rigid_modes = (RigidMode("rotation", (1.0,)),)
    _form = "cos"

    def _compute_roots(self, n: int) -> np.ndarray:
        return whole_wave_roots(n)
