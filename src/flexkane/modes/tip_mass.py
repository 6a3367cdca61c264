"""Cantilever carrying a rigid body at its tip: the ``clamped-free-tip-mass`` family.

A tip body of mass ``M`` [kg] and moment of inertia ``J`` [kg m^2] about the tip adds, at
``x = L``, the shear ``EI y''' = -M y_tt`` and the moment ``EI y'' = J y_x,tt`` to eq. 8.1. With
``mu = M / (rho L)``, ``kappa = J / (rho L^3)`` and ``y = Phi(xi) cos(p t)`` (``p`` of eq. 8.7):

    Phi'''(1) = -mu lambda^4 Phi(1),     Phi''(1) = kappa lambda^4 Phi'(1).

Eliminating ``Phi = cosh a - cos a - sigma (sinh a - sin a)`` (clamped root) gives the frequency
equation, divided by ``2 cosh lambda`` to stay finite:

    (sech l + c) + mu l (c tanh l - s) - kappa l^3 (s + c tanh l) + mu kappa l^4 (sech l - c) = 0

with ``c = cos l``, ``s = sin l``. It reduces to eq. 8.6 for ``mu = kappa = 0``; for large ``mu``
its first root tends to ``(3 / mu)^(1/4)`` (a mass on a massless spring of stiffness ``3 EI / L^3``)
and the others to the clamped-pinned roots.

The eigenfunctions are orthogonal with respect to the mass of beam *and* tip body, so they are
normalised to

    int_0^1 Phi_i Phi_j dxi + mu Phi_i(1) Phi_j(1) + kappa Phi_i'(1) Phi_j'(1) = delta_ij,

which is ``int_0^1 Phi_i^2 dxi = 1`` when the tip body vanishes; with a tip body the beam-only
integrals ``G_ij`` of eq. 8.22 are not diagonal.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from ..errors import ModelError
from .eigen import EigenFamily
from .exponential_form import evaluate
from .roots import cantilever_roots, scan_roots

__all__ = ["ClampedFreeTipMass"]


def _ratio(value: Any, path: str, what: str) -> float:
    if value is None:
        raise ModelError(path, what, None, hint="this option is required", show_given=False)
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise ModelError(path, what, value) from None
    if not math.isfinite(number) or number < 0.0:
        raise ModelError(path, what, value)
    return number


class ClampedFreeTipMass(EigenFamily):
    """Cantilever with a rigid tip body.

    Parameters
    ----------
    mass_ratio : float
        ``mu = M_tip / (rho L)``, tip mass over beam mass [-], ``>= 0``.
    inertia_ratio : float
        ``kappa = J_tip / (rho L^3)``, moment of inertia of the tip body about the tip over
        ``rho L^3`` [-], ``>= 0``.
    """

    name = "clamped-free-tip-mass"
    boundary = "clamped-free"
    option_names = ("mass_ratio", "inertia_ratio")
    numeric_options = ("mass_ratio", "inertia_ratio")

    def __init__(self, mass_ratio: Any = None, inertia_ratio: Any = None):
        mu = _ratio(mass_ratio, "mass_ratio",
                    "mass_ratio = M_tip / (rho L) [-], a number >= 0")
        kappa = _ratio(inertia_ratio, "inertia_ratio",
                       "inertia_ratio = J_tip / (rho L^3) [-], a number >= 0")
        super().__init__({"mass_ratio": mu, "inertia_ratio": kappa})
        self.mass_ratio = mu
        self.inertia_ratio = kappa

    def frequency_function(self, lam: np.ndarray) -> np.ndarray:
        """Left side of the frequency equation (module docstring), shape of ``lam``."""
        lam = np.asarray(lam, dtype=float)
        mu, kappa = self.mass_ratio, self.inertia_ratio
        c, s, t = np.cos(lam), np.sin(lam), np.tanh(lam)
        sech = np.exp(-lam) * 2.0 / (1.0 + np.exp(-2.0 * lam))
        return ((sech + c) + mu * lam * (c * t - s) - kappa * lam ** 3 * (s + c * t)
                + mu * kappa * lam ** 4 * (sech - c))

    def _compute_roots(self, n: int) -> np.ndarray:
        if self.mass_ratio == 0.0 and self.inertia_ratio == 0.0:
            return cantilever_roots(n)
        # a tip body lowers every frequency, so lambda_n is below the cantilever's
        upper = float(cantilever_roots(n)[-1]) + 0.5
        return scan_roots(self.frequency_function, n, upper)

    def _raw_coefficients(self, lam: np.ndarray) -> np.ndarray:
        # sigma from the shear condition, whose denominator (cosh l + cos l) + mu l (sinh l - sin l)
        # never vanishes; all terms multiplied by 2 e^-l
        mu = self.mass_ratio
        c, s, E = np.cos(lam), np.sin(lam), np.exp(-lam)
        num = (1.0 - E * E - 2.0 * E * s) + mu * lam * (1.0 + E * E - 2.0 * E * c)
        den = (1.0 + E * E + 2.0 * E * c) + mu * lam * (1.0 - E * E - 2.0 * E * s)
        sigma = num / den
        P = (E + c + s + mu * lam * (c - s - E)) / den
        return np.vstack([P, 0.5 * (1.0 + sigma), -np.ones_like(lam), sigma])

    def _extra_norm_squared(self, lam: np.ndarray, coeffs: np.ndarray) -> np.ndarray:
        tip = np.ones(1)
        value = evaluate(lam, coeffs, tip, 0)[:, 0]
        slope = evaluate(lam, coeffs, tip, 1)[:, 0]
        return self.mass_ratio * value ** 2 + self.inertia_ratio * slope ** 2
