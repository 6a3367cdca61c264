"""Eigenfunctions of uniform Euler-Bernoulli beams under the classical end conditions.

Every family is written in the decaying-exponential form of
:mod:`flexkane.modes.exponential_form`; the coefficients below are the textbook ones multiplied
out with ``E = e^-lambda``, so that none of them is computed by cancellation. With
``c = cos lambda``, ``s = sin lambda``:

* clamped-free (eq. 8.4, 8.6): ``Phi = cosh a - cos a - sigma (sinh a - sin a)``,
  ``sigma = (cosh l + cos l) / (sinh l + sin l)``, ``cos l cosh l + 1 = 0``.
* clamped-clamped: same form, ``sigma = (cosh l - cos l) / (sinh l - sin l)``,
  ``cos l cosh l - 1 = 0``.
* clamped-pinned: same form and sigma as clamped-clamped, ``tan l = tanh l``.
* free-free: ``Phi = cosh a + cos a - sigma (sinh a + sin a)``, sigma and roots of
  clamped-clamped; rigid modes ``1`` and ``sqrt(12) (xi - 1/2)``.
* pinned-free: ``Phi = sin a + (sin l / sinh l) sinh a``, ``tan l = tanh l``; rigid mode
  ``sqrt(3) xi`` (rotation about the pin).
* pinned-pinned: ``Phi = sqrt(2) sin(i pi xi)``.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from ..errors import ModelError
from .base import RigidMode
from .eigen import EigenFamily
from .roots import cantilever_roots, clamped_clamped_roots, tan_tanh_roots

__all__ = ["ClampedFree", "ClampedClamped", "ClampedPinned", "FreeFree", "PinnedFree",
           "PinnedPinned", "cosh_cos_coefficients"]


def cosh_cos_coefficients(lam: np.ndarray, plus: bool) -> np.ndarray:
    """Coefficients ``P, Q, R, S`` of ``cosh a - cos a - sigma (sinh a - sin a)``.

    Parameters
    ----------
    lam : numpy.ndarray
        ``lambda_i``, shape ``(n,)``.
    plus : bool
        ``True`` for ``sigma = (cosh l + cos l) / (sinh l + sin l)`` (eq. 8.4), ``False`` for
        ``sigma = (cosh l - cos l) / (sinh l - sin l)``.

    Returns
    -------
    numpy.ndarray
        Shape ``(4, n)``. ``P = (1 - sigma) e^l / 2`` and ``Q = (1 + sigma) / 2`` weight
        ``e^{l (xi - 1)}`` and ``e^{-l xi}``; ``R = -1``, ``S = sigma``.
    """
    c, s, E = np.cos(lam), np.sin(lam), np.exp(-lam)
    sign = 1.0 if plus else -1.0
    # 2 e^-l (sinh l +- sin l) and 2 e^-l (cosh l +- cos l)
    den = 1.0 - E * E + sign * 2.0 * E * s
    num = 1.0 + E * E + sign * 2.0 * E * c
    sigma = num / den
    # (1 - sigma) e^l / 2, expanded: (+-(s - c) - e^-l) / den
    P = (sign * (s - c) - E) / den
    return np.vstack([P, 0.5 * (1.0 + sigma), -np.ones_like(lam), sigma])


class ClampedFree(EigenFamily):
    """The cantilever of the chapter: eigenfunctions of eq. 8.4 with the roots of eq. 8.6.

    ``int_0^1 Phi_i Phi_j dxi = delta_ij`` (eq. 8.8) and ``int_0^1 Phi_i'' Phi_j'' dxi =
    lambda_i^4 delta_ij`` (eq. 8.9), ``Phi_i''(0) = 2 lambda_i^2 > 0``, ``Phi_i(1) = 2 (-1)^(i+1)``.

    Parameters
    ----------
    roots : sequence of float, optional
        Values of ``lambda_i`` *as typed* (e.g. ``[1.875]`` in the chapter's notebook). Then
        ``Phi_i`` is eq. 8.4 evaluated with these values exactly as written, without the
        renormalisation that would make up for their rounding, so a typed model is reproduced
        exactly; ``n`` may not exceed their number.
    """

    name = "clamped-free"
    boundary = "clamped-free"
    option_names = ("roots",)
    numeric_options = ("roots",)

    def __init__(self, roots: Any = None):
        typed = None
        if roots is not None:
            try:
                typed = tuple(float(r) for r in np.atleast_1d(np.asarray(roots, dtype=float)))
            except (TypeError, ValueError):
                raise ModelError("roots", "a list of positive numbers lambda_i",
                                 roots) from None
            if not typed or not all(math.isfinite(r) and r > 0.0 for r in typed):
                raise ModelError("roots", "a list of positive numbers lambda_i", roots)
        super().__init__({} if typed is None else {"roots": typed})
        self._typed = typed
        self.normalise = typed is None

    @property
    def max_modes(self) -> int | None:
        return None if self._typed is None else len(self._typed)

    def _compute_roots(self, n: int) -> np.ndarray:
        if self._typed is not None:
            return np.array(self._typed[:n])
        return cantilever_roots(n)

    def _raw_coefficients(self, lam: np.ndarray) -> np.ndarray:
        return cosh_cos_coefficients(lam, plus=True)


class ClampedClamped(EigenFamily):
    """Beam clamped at both ends: ``Phi = Phi' = 0`` at ``xi = 0`` and ``xi = 1``;
    ``cos l cosh l = 1`` (``lambda_1 = 4.7300407449``)."""

    name = "clamped-clamped"
    boundary = "clamped-clamped"

    def _compute_roots(self, n: int) -> np.ndarray:
        return clamped_clamped_roots(n)

    def _raw_coefficients(self, lam: np.ndarray) -> np.ndarray:
        return cosh_cos_coefficients(lam, plus=False)


class ClampedPinned(EigenFamily):
    """Beam clamped at ``xi = 0`` and pinned at ``xi = 1``; ``tan l = tanh l``
    (``lambda_1 = 3.9266023120``)."""

    name = "clamped-pinned"
    boundary = "clamped-pinned"

    def _compute_roots(self, n: int) -> np.ndarray:
        return tan_tanh_roots(n)

    def _raw_coefficients(self, lam: np.ndarray) -> np.ndarray:
        return cosh_cos_coefficients(lam, plus=False)


class FreeFree(EigenFamily):
    """Beam free at both ends; elastic modes only, roots those of clamped-clamped.

    ``phi`` excludes the two rigid-body modes; they are ``rigid_modes``: the translation
    ``Phi = 1`` and the rotation about the centre ``Phi = sqrt(12) (xi - 1/2)``, both
    mass-normalised and orthogonal to the elastic modes.
    """

    name = "free-free"
    boundary = "free-free"
    rigid_modes = (RigidMode("translation", (1.0,)),
                   RigidMode("rotation about the centre", (-math.sqrt(3.0), math.sqrt(12.0))))

    def _compute_roots(self, n: int) -> np.ndarray:
        return clamped_clamped_roots(n)

    def _raw_coefficients(self, lam: np.ndarray) -> np.ndarray:
        # cosh a + cos a - sigma (sinh a + sin a): the clamped-clamped exponentials, R = 1, S = -sigma
        coeffs = cosh_cos_coefficients(lam, plus=False)
        coeffs[2] = 1.0
        coeffs[3] = -coeffs[3]
        return coeffs


class PinnedFree(EigenFamily):
    """Beam pinned at ``xi = 0`` and free at ``xi = 1``; ``tan l = tanh l``.

    ``phi`` excludes the rigid rotation about the pin, listed in ``rigid_modes`` as
    ``Phi = sqrt(3) xi``.
    """

    name = "pinned-free"
    boundary = "pinned-free"
    rigid_modes = (RigidMode("rotation about the pin", (0.0, math.sqrt(3.0))),)

    def _compute_roots(self, n: int) -> np.ndarray:
        return tan_tanh_roots(n)

    def _raw_coefficients(self, lam: np.ndarray) -> np.ndarray:
        s, E = np.sin(lam), np.exp(-lam)
        # (sin l / sinh l) sinh a = sin l (e^{a - l} - e^{-l} e^{-a}) / (1 - e^{-2 l})
        P = s / (1.0 - E * E)
        return np.vstack([P, -E * P, np.zeros_like(lam), np.ones_like(lam)])


class PinnedPinned(EigenFamily):
    """Simply supported beam: ``Phi_i = sqrt(2) sin(i pi xi)``, ``lambda_i = i pi``."""

    name = "pinned-pinned"
    boundary = "pinned-pinned"

    def _compute_roots(self, n: int) -> np.ndarray:
        return np.arange(1, n + 1) * math.pi

    def _raw_coefficients(self, lam: np.ndarray) -> np.ndarray:
        zero = np.zeros_like(lam)
        return np.vstack([zero, zero, zero, np.ones_like(lam)])

    def quadrature_order(self, n: int) -> int:
        return n + 30
