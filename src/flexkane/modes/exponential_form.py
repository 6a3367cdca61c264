"""Beam eigenfunctions written with decaying exponentials only.

Every solution of ``Phi'''' = lambda^4 Phi`` (eq. 8.1 after separation of variables, eq. 8.3) is a
combination of ``cosh, sinh, cos, sin`` of ``a = lambda xi``. Written as in eq. 8.4, the hyperbolic
terms grow like ``e^lambda / 2`` and cancel each other to leave an ``O(1)`` function: for
``lambda_15 ~ 46`` the cancellation eats all sixteen digits. Rewriting

    cosh a - sigma sinh a = ((1 - sigma) e^a + (1 + sigma) e^-a) / 2

with ``1 - sigma`` obtained without subtraction, every function of this package is stored as

    Phi(xi) = P e^{lambda (xi - 1)} + Q e^{-lambda xi} + R cos(lambda xi) + S sin(lambda xi)

with ``O(1)`` coefficients ``P, Q, R, S`` and only decaying exponentials on ``[0, 1]``. Its
derivatives are exact:

    d^k Phi / d xi^k = lambda^k [P e^{lambda (xi - 1)} + (-1)^k Q e^{-lambda xi}
                                 + R cos(lambda xi + k pi/2) + S sin(lambda xi + k pi/2)].
"""

from __future__ import annotations

import numpy as np

__all__ = ["evaluate", "norm_squared"]


def evaluate(lam: np.ndarray, coeffs: np.ndarray, xi: np.ndarray, deriv: int) -> np.ndarray:
    """Evaluate the exponential form or one of its derivatives.

    Parameters
    ----------
    lam : numpy.ndarray
        Eigenvalue parameters ``lambda_i``, shape ``(n,)``.
    coeffs : numpy.ndarray
        Coefficients ``P, Q, R, S`` as rows, shape ``(4, n)``.
    xi : numpy.ndarray
        Abscissae ``x / L`` in ``[0, 1]``, shape ``(m,)``.
    deriv : int
        Order ``k`` of the derivative with respect to ``xi`` (any non-negative integer).

    Returns
    -------
    numpy.ndarray
        ``d^k Phi_i / d xi^k``, shape ``(n, m)``.
    """
    P, Q, R, S = (c[:, None] for c in coeffs)
    lam_col = lam[:, None]
    a = lam_col * xi[None, :]
    cos_a, sin_a = np.cos(a), np.sin(a)
    # cos(a + k pi/2) and sin(a + k pi/2) by exact quarter turns
    turn = deriv % 4
    if turn == 0:
        c, s = cos_a, sin_a
    elif turn == 1:
        c, s = -sin_a, cos_a
    elif turn == 2:
        c, s = -cos_a, -sin_a
    else:
        c, s = sin_a, -cos_a
    sign = -1.0 if deriv % 2 else 1.0
    value = P * np.exp(lam_col * (xi[None, :] - 1.0)) + sign * Q * np.exp(-a) + R * c + S * s
    return value * lam_col ** deriv


def norm_squared(lam: np.ndarray, coeffs: np.ndarray) -> np.ndarray:
    """Exact ``int_0^1 Phi_i^2 dxi`` of solutions of ``Phi'''' = lambda^4 Phi``.

    Uses the identity, checked by differentiation,

        4 lambda^4 int_0^1 Phi^2 dxi
            = [xi (lambda^4 Phi^2 - 2 Phi' Phi''' + Phi''^2) + 3 Phi Phi''' - Phi' Phi'']_0^1

    written with the scaled derivatives ``phi_k = Phi^(k) / lambda^k`` so every term is ``O(1)``.

    Parameters
    ----------
    lam : numpy.ndarray
        Eigenvalue parameters ``lambda_i > 0``, shape ``(n,)``.
    coeffs : numpy.ndarray
        Coefficients ``P, Q, R, S``, shape ``(4, n)``.

    Returns
    -------
    numpy.ndarray
        Shape ``(n,)``.
    """
    ends = np.array([0.0, 1.0])
    scaled = [evaluate(lam, coeffs, ends, k) / lam[:, None] ** k for k in range(4)]
    p0, p1, p2, p3 = scaled
    bracket = ends[None, :] * (p0 ** 2 - 2.0 * p1 * p3 + p2 ** 2) \
        + (3.0 * p0 * p3 - p1 * p2) / lam[:, None]
    return 0.25 * (bracket[:, 1] - bracket[:, 0])
