"""Rayleigh-Ritz polynomials ``Phi_k = xi^(k+1)``, ``k = 1..n`` (``xi^2, xi^3, ...``).

They satisfy the geometric conditions of a clamped root, ``Phi(0) = Phi'(0) = 0``, and nothing at
the tip: the natural conditions of eq. 8.2 are met only in the limit. They are not normalised and
not orthogonal; their Gram matrix is a Hilbert-like matrix whose condition number grows
roughly tenfold per term, so more than about ten terms buys nothing in double precision.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from .base import ShapeFamily, as_abscissae

__all__ = ["Polynomial"]


class Polynomial(ShapeFamily):
    """Monomials ``Phi_k = (x / L)^(k+1)`` for a clamped root (Rayleigh-Ritz)."""

    name = "polynomial"
    boundary = "clamped-free"

    def phi(self, xi: Any, n: int, deriv: int = 0) -> np.ndarray:
        """``d^d Phi_k / d xi^d = (k+1)! / (k+1-d)! xi^(k+1-d)``; shape ``(n, len(xi))``."""
        x = as_abscissae(xi)
        deriv = self._check_deriv(deriv)
        n = self._check_n(n)
        out = np.zeros((n, x.size))
        for k in range(1, n + 1):
            power = k + 1
            if deriv <= power:
                factor = math.factorial(power) / math.factorial(power - deriv)
                out[k - 1] = factor * x ** (power - deriv)
        return out

    def quadrature_order(self, n: int) -> int:
        # products xi^(2n+2) times x^2 weights: exact from n + 3 nodes
        return n + 4
