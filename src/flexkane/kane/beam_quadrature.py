"""Numeric values of atoms along a beam, and of the integrals of their products.

Integrals use Gauss-Legendre quadrature on [0, L] of the order that :mod:`flexkane.modes.integrals`
verifies for the family and mode count (products of shape functions and of their derivatives to
about 1e-13 relative); products that involve the foreshortening atoms
``d_ij(x) = int_0^x Phi_i' Phi_j' dxi`` (themselves quadratic in the shape functions) use twice that
order, and ``d_ij`` at the nodes comes from :func:`flexkane.modes.integrals.foreshortening`.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

__all__ = ["AtomEvaluator"]


@lru_cache(maxsize=32)
def _leggauss(order: int) -> tuple[np.ndarray, np.ndarray]:
    nodes, weights = np.polynomial.legendre.leggauss(order)
    return (nodes + 1.0) / 2.0, weights / 2.0  # on [0, 1]


class AtomEvaluator:
    """Evaluate atoms of :mod:`flexkane.kane.modal_field` for one beam.

    Parameters
    ----------
    L : float
        Beam length [m].
    family : ShapeFamily
        Transverse shape functions; ``family.phi(xi, n, deriv)`` has shape (n, len(xi)).
    n : int
        Number of transverse shape functions.
    axial_family : ShapeFamily, optional
        Axial shape functions.
    n_axial : int
        Number of axial shape functions.
    """

    def __init__(self, *, L: float, family, n: int, axial_family=None, n_axial: int = 0):
        self.L = float(L)
        self.family = family
        self.n = int(n)
        self.axial_family = axial_family
        self.n_axial = int(n_axial)
        from ..modes.integrals import quadrature_order

        order = quadrature_order(family, self.n)
        if axial_family is not None and self.n_axial:
            order = max(order, quadrature_order(axial_family, self.n_axial))
        self._rules = {False: self._rule(order), True: self._rule(2 * order)}
        self.xi, self.weights, self.x = self._rules[False]
        self._values: dict = {}
        self._dfs_cache: dict = {}

    def _rule(self, order: int):
        xi, w = _leggauss(order)
        return xi, w * self.L, xi * self.L   # nodes on [0, 1], weights for [0, L] [m], nodes [m]

    # ------------------------------------------------------------------ atom values
    def _phi(self, xi: np.ndarray, deriv: int) -> np.ndarray:
        return self.family.phi(xi, self.n, deriv) / self.L ** deriv

    def _psi(self, xi: np.ndarray, deriv: int) -> np.ndarray:
        return self.axial_family.phi(xi, self.n_axial, deriv) / self.L ** deriv

    def _dfs(self, i: int, j: int, xi: np.ndarray) -> np.ndarray:
        """d_ij at stations ``xi * L`` [1/m] (all pairs computed once per set of stations)."""
        from ..modes.integrals import foreshortening

        key = xi.tobytes()
        if key not in self._dfs_cache:
            self._dfs_cache[key] = foreshortening(self.family, self.n, self.L, np.clip(xi, 0.0, 1.0) * self.L)
        return self._dfs_cache[key][i - 1, j - 1]

    def values_at(self, atom, xi: np.ndarray, deriv: int = 0) -> np.ndarray:
        """Values of ``atom`` (or its x-derivative of order ``deriv``) at ``xi = x/L``, shape (len(xi),)."""
        kind = atom[0]
        xi = np.asarray(xi, dtype=float)
        if kind == "1":
            return np.ones_like(xi) if deriv == 0 else np.zeros_like(xi)
        if kind == "x":
            return xi * self.L if deriv == 0 else (np.ones_like(xi) if deriv == 1 else np.zeros_like(xi))
        if kind == "phi":
            return self._phi(xi, deriv)[atom[1] - 1]
        if kind == "psi":
            return self._psi(xi, deriv)[atom[1] - 1]
        if kind == "dphi":
            return self._phi(xi, deriv + 1)[atom[1] - 1]
        if kind == "d":
            if deriv == 0:
                return self._dfs(atom[1], atom[2], xi)
            if deriv == 1:
                d1 = self._phi(xi, 1)
                return d1[atom[1] - 1] * d1[atom[2] - 1]
            raise ValueError("only the first derivative of a foreshortening atom is available")
        raise ValueError(f"unknown atom {atom!r}")

    def _nodes(self, atom, deriv: int = 0, fine: bool = False) -> np.ndarray:
        key = (atom, deriv, fine)
        if key not in self._values:
            self._values[key] = self.values_at(atom, self._rules[fine][0], deriv)
        return self._values[key]

    # ------------------------------------------------------------------ integrals
    def integral(self, a, b) -> float:
        """``int_0^L a(x) b(x) dx`` [m * units of a * units of b]."""
        fine = a[0] == "d" or b[0] == "d"
        weights = self._rules[fine][1]
        return float(np.sum(weights * self._nodes(a, fine=fine) * self._nodes(b, fine=fine)))

    def profile_integral(self, a, profile) -> float:
        """``int_0^L a(x) h(x) dx`` for a function ``h`` of x [m] (a distributed load's profile),
        with twice the verified order of the modal constants."""
        xi, weights, x = self._rules[True]
        h = np.broadcast_to(np.asarray(profile(x), dtype=float), x.shape)
        return float(np.sum(weights * self._nodes(a, fine=True) * h))

    def derivative_integral(self, a, b, deriv: int) -> float:
        """``int_0^L a^(k)(x) b^(k)(x) dx`` with k = ``deriv``."""
        return float(np.sum(self.weights * self._nodes(a, deriv) * self._nodes(b, deriv)))

    def at(self, atom, x: float, deriv: int = 0) -> float:
        """Value of an atom or of its derivative at the station x [m]."""
        return float(self.values_at(atom, np.array([x / self.L]), deriv)[0])

    def shear_moment(self, kind: str, i: int, j: int) -> float:
        """Constants of eq. 8.28 (see :meth:`BeamConstants.shear_moment`)."""
        phi_i = ("phi", i)
        if kind == "M0":
            return self.at(phi_i, 0.0, 2)
        if kind == "V0":
            return self.at(phi_i, 0.0, 3)
        if kind == "J":
            return float(np.sum(self.weights * self._nodes(phi_i, 4)))
        if kind == "Jx":
            return float(np.sum(self.weights * self.x * self._nodes(phi_i, 4)))
        if kind == "JPhi":
            return float(np.sum(self.weights * self._nodes(("phi", j)) * self._nodes(phi_i, 4)))
        raise ValueError(kind)
