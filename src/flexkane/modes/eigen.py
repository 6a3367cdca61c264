"""Common machinery of the eigenfunction families (normalisation, sign, caching of roots).

A concrete family gives its frequency equation's roots and the raw coefficients ``P, Q, R, S`` of
its eigenfunctions in the exponential form of :mod:`flexkane.modes.exponential_form`. This class
then

* normalises them to ``int_0^1 Phi_i^2 dxi = 1`` (plus the tip-body terms where a family has
  them), the normalisation of eq. 8.4, with the exact integral of
  :func:`~flexkane.modes.exponential_form.norm_squared` rather than quadrature;
* fixes the sign: **the first derivative of ``Phi_i`` that is not zero at ``xi = 0`` is
  positive** (``Phi_i''(0) > 0`` at a clamped root, as in eq. 8.4; ``Phi_i'(0) > 0`` at a pinned
  root; ``Phi_i(0) > 0`` at a free root).
"""

from __future__ import annotations

import abc
from typing import Any

import numpy as np

from .base import ShapeFamily, as_abscissae
from .exponential_form import evaluate, norm_squared

__all__ = ["EigenFamily"]


class EigenFamily(ShapeFamily):
    """Base class of families made of the eigenfunctions of a uniform beam.

    Subclasses implement :meth:`_compute_roots` and :meth:`_raw_coefficients`, and may override
    :meth:`_extra_norm_squared` (tip bodies) and ``normalise`` (``False`` keeps the formula as
    written, used for roots typed by the user).
    """

    #: Whether to rescale to unit norm and fix the sign (``False`` only for typed roots).
    normalise: bool = True

    def __init__(self, options: dict[str, Any] | None = None):
        super().__init__(options)
        self._lam = np.empty(0)
        self._coeffs = np.empty((4, 0))

    # ------------------------------------------------------------------ to implement
    @abc.abstractmethod
    def _compute_roots(self, n: int) -> np.ndarray:
        """The first ``n`` roots of the frequency equation, shape ``(n,)``."""

    @abc.abstractmethod
    def _raw_coefficients(self, lam: np.ndarray) -> np.ndarray:
        """Unnormalised coefficients ``P, Q, R, S`` for the roots ``lam``, shape ``(4, n)``."""

    def _extra_norm_squared(self, lam: np.ndarray, coeffs: np.ndarray) -> np.ndarray:
        """Terms added to ``int_0^1 Phi^2 dxi`` in the mass normalisation (tip bodies)."""
        return np.zeros(lam.shape)

    # ------------------------------------------------------------------ contract
    def roots(self, n: int) -> np.ndarray:
        """Eigenvalue parameters ``lambda_i`` (dimensionless), shape ``(n,)``."""
        n = self._check_n(n)
        self._ensure(n)
        return self._lam[:n].copy()

    def coefficients(self, n: int) -> tuple[np.ndarray, np.ndarray]:
        """Roots, shape ``(n,)``, and normalised coefficients ``P, Q, R, S``, shape ``(4, n)``."""
        n = self._check_n(n)
        self._ensure(n)
        return self._lam[:n].copy(), self._coeffs[:, :n].copy()

    def phi(self, xi: Any, n: int, deriv: int = 0) -> np.ndarray:
        """``d^k Phi_i / d xi^k`` at ``xi`` (shape ``(m,)``) for ``i = 1..n``; shape ``(n, m)``."""
        x = as_abscissae(xi)
        deriv = self._check_deriv(deriv)
        n = self._check_n(n)
        self._ensure(n)
        return evaluate(self._lam[:n], self._coeffs[:, :n], x, deriv)

    def quadrature_order(self, n: int) -> int:
        """Gauss-Legendre order for products of the first ``n`` modes (verified by the caller)."""
        lam_n = float(self.roots(n)[-1])
        return int(1.5 * lam_n) + 30

    # ------------------------------------------------------------------ internals
    def _ensure(self, n: int) -> None:
        if self._lam.size >= n:
            return
        lam = np.asarray(self._compute_roots(n), dtype=float)
        coeffs = np.asarray(self._raw_coefficients(lam), dtype=float)
        if self.normalise:
            norm = np.sqrt(norm_squared(lam, coeffs) + self._extra_norm_squared(lam, coeffs))
            coeffs = coeffs / norm
            coeffs = coeffs * self._sign(lam, coeffs)
        self._lam, self._coeffs = lam, coeffs

    @staticmethod
    def _sign(lam: np.ndarray, coeffs: np.ndarray) -> np.ndarray:
        """+1 or -1 per mode so that the first non-zero derivative at ``xi = 0`` is positive."""
        origin = np.zeros(1)
        sign = np.zeros(lam.shape)
        for k in range(4):
            value = evaluate(lam, coeffs, origin, k)[:, 0] / lam ** k
            undecided = (sign == 0.0) & (np.abs(value) > 1e-6)
            sign[undecided] = np.sign(value[undecided])
        sign[sign == 0.0] = 1.0
        return sign
