"""High-precision (mpmath) reference eigenfunctions written as in the textbooks.

Each family is ``A cosh a + B sinh a + C cos a + D sin a`` with ``a = lambda xi``, evaluated with
120 significant digits so that the cancellation of eq. 8.4 is harmless. The reference is normalised
by the same exact identity as the package but in mpmath arithmetic, and signed so that the first
non-zero derivative at ``xi = 0`` is positive.
"""

from __future__ import annotations

import mpmath as mp
import numpy as np

DPS = 120


def _textbook(name: str, lam, mu=0, kappa=0):
    """Coefficients (A, B, C, D) of the unnormalised textbook eigenfunction."""
    ch, sh, c, s = mp.cosh(lam), mp.sinh(lam), mp.cos(lam), mp.sin(lam)
    if name == "clamped-free":                    # eq. 8.4
        sigma = (ch + c) / (sh + s)
        return 1, -sigma, -1, sigma
    if name in ("clamped-clamped", "clamped-pinned"):
        sigma = (ch - c) / (sh - s)
        return 1, -sigma, -1, sigma
    if name == "free-free":
        sigma = (ch - c) / (sh - s)
        return 1, -sigma, 1, -sigma
    if name == "pinned-free":
        return 0, s / sh, 0, 1
    if name == "clamped-free-tip-mass":
        sigma = ((sh - s) + mu * lam * (ch - c)) / ((ch + c) + mu * lam * (sh - s))
        return 1, -sigma, -1, sigma
    raise KeyError(name)


def _derivative(coeffs, lam, xi, k):
    A, B, C, D = coeffs
    a = lam * xi
    hyper = (A * mp.cosh(a) + B * mp.sinh(a)) if k % 2 == 0 else (A * mp.sinh(a) + B * mp.cosh(a))
    shift = k * mp.pi / 2
    trig = C * mp.cos(a + shift) + D * mp.sin(a + shift)
    return lam ** k * (hyper + trig)


def _root(name: str, guess: float, mu=0, kappa=0):
    def equation(l):
        c, s, t, sech = mp.cos(l), mp.sin(l), mp.tanh(l), mp.sech(l)
        if name == "clamped-free":
            return c + sech
        if name in ("clamped-clamped", "free-free"):
            return c - sech
        if name in ("clamped-pinned", "pinned-free"):
            return s - c * t
        return ((sech + c) + mu * l * (c * t - s) - kappa * l ** 3 * (s + c * t)
                + mu * kappa * l ** 4 * (sech - c))
    return mp.findroot(equation, mp.mpf(guess))


def reference(name: str, i: int, guess: float, xi: np.ndarray, mu=0.0, kappa=0.0):
    """Root and derivatives 0..4 of the ``i``-th mass-normalised eigenfunction.

    Returns
    -------
    root : float
    values : numpy.ndarray
        Shape ``(5, len(xi))``.
    """
    with mp.workdps(DPS):
        mu_, kappa_ = mp.mpf(mu), mp.mpf(kappa)
        lam = _root(name, guess, mu_, kappa_)
        coeffs = _textbook(name, lam, mu_, kappa_)
        ends = {e: [_derivative(coeffs, lam, mp.mpf(e), k) / lam ** k for k in range(4)]
                for e in (0, 1)}

        def bracket(e):
            p0, p1, p2, p3 = ends[e]
            return e * (p0 ** 2 - 2 * p1 * p3 + p2 ** 2) + (3 * p0 * p3 - p1 * p2) / lam

        norm2 = (bracket(1) - bracket(0)) / 4
        norm2 += mu_ * (ends[1][0]) ** 2 + kappa_ * (ends[1][1] * lam) ** 2
        scale = 1 / mp.sqrt(norm2)
        for k in range(4):
            if abs(ends[0][k]) > mp.mpf("1e-30"):
                scale *= mp.sign(ends[0][k])
                break
        values = np.array([[float(_derivative(coeffs, lam, mp.mpf(float(x)), k) * scale)
                            for x in xi] for k in range(5)])
        return float(lam), values
