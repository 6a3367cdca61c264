"""Rayleigh-Ritz polynomials: ``Phi_k = xi^(k+1)``, ``k = 1..n`` (``xi^2, xi^3, ...``) for bending,
``Theta_k = xi^k`` (``xi, xi^2, ...``) for torsion and ``psi_k = xi^k`` for axial deformation.

The bending polynomials satisfy the geometric conditions of a clamped root,
``Phi(0) = Phi'(0) = 0``, the torsion and axial ones those of a fixed root (``Theta(0) = 0``), and
nothing at the tip: the natural conditions (eq. 8.2; ``GJ Theta'(L) = 0`` and ``EA psi'(L) = 0``
at a free tip) are met only in the limit, so a torque or an axial force carried at the tip is
represented from the first function on (``xi`` is the static twist of a shaft under a tip torque),
where the sine modes of :mod:`flexkane.modes.torsion` and :mod:`flexkane.modes.axial` have
``Theta'(1) = 0`` and converge as ``1/n``. They are not normalised and not orthogonal; their Gram
matrix is a Hilbert-like matrix whose condition number grows roughly tenfold per term, so more
than about ten terms buys nothing in double precision.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from .base import ShapeFamily, as_abscissae

__all__ = ["Polynomial", "TorsionPolynomial", "AxialPolynomial"]


class Polynomial(ShapeFamily):
    """Monomials ``Phi_k = (x / L)^(k+1)`` for a clamped root (Rayleigh-Ritz)."""

    name = "polynomial"
    boundary = "clamped-free"
    #: The power of the first function: ``Phi_k = xi^(k + first_power - 1)``.
    first_power = 2

    def phi(self, xi: Any, n: int, deriv: int = 0) -> np.ndarray:
        """``d^d Phi_k / d xi^d = p! / (p-d)! xi^(p-d)``, ``p = k + first_power - 1``; shape ``(n, len(xi))``."""
        x = as_abscissae(xi)
        deriv = self._check_deriv(deriv)
        n = self._check_n(n)
        out = np.zeros((n, x.size))
        for k in range(1, n + 1):
            power = k + self.first_power - 1
            if deriv <= power:
                factor = math.factorial(power) / math.factorial(power - deriv)
                out[k - 1] = factor * x ** (power - deriv)
        return out

    def quadrature_order(self, n: int) -> int:
        # products xi^(2n+2) times x^2 weights: exact from n + 3 nodes
        return n + 4


class TorsionPolynomial(Polynomial):
    """Monomials ``Theta_k = (x / L)^k`` of the twist of a shaft with a fixed root (Rayleigh-Ritz)."""

    name = "torsion-polynomial"
    boundary = "fixed-free"
    kind = "torsion"
    first_power = 1


class AxialPolynomial(Polynomial):
    """Monomials ``psi_k = (x / L)^k`` of the axial displacement of a bar with a fixed root."""

    name = "axial-polynomial"
    boundary = "fixed-free"
    kind = "axial"
    first_power = 1
