"""Static correction shapes: a beam's basis completed by its static response to what it carries.

A beam that carries another beam, a body or a load at its tip is loaded there by a force, a moment
and a torque. Free-vibration modes of a cantilever cannot represent that load: their natural tip
conditions (``Phi''(1) = Phi'''(1) = 0`` in bending, ``Theta'(1) = 0`` in torsion and axial
deformation) are those of a free tip, so the modal series of the deflection under a tip load
converges only slowly (in torsion and axial stretch as ``1/n``: an L-frame of two welded beams,
whose second leg twists the first one's tip, stops at +0.4 % on its first frequencies with 40
functions). The static deflection and twist of the beam under a unit load at the tip complete the
basis (a Ritz basis with *static correction shapes*):

* bending (``kind == "transverse"``), clamped root: the deflection under a unit tip force,
  ``(3 xi^2 - xi^3) / 2``, and under a unit tip moment, ``xi^2`` (``Phi = Phi' = 0`` at the root);
* torsion and axial deformation, fixed root: the twist under a unit tip torque and the stretch
  under a unit tip force, both ``xi`` (``Theta = 0`` at the root).

:class:`StaticCorrection` keeps the number of functions of its base family: the basis of ``n``
functions is the first ``n - k`` functions of the base family followed by ``k`` correction shapes
(all of them, two in bending and one in torsion or stretch, but at most ``n - 1``: the family's
first function always stays, so a basis of one function is the family's), each made orthogonal, with respect to the beam's mass (``int_0^1 Phi_i Phi_j dxi``), to
the functions before it and mass-normalised. A correction shape that the functions before it
already span (to 1e-10 of its norm) is dropped with a warning and the next function of the base
family takes its place, so the mass matrix never becomes singular. The functions are ordinary shape
functions (exact derivatives to order 4): every use of a family (modal constants, invariants,
animation) works with them unchanged.
"""

from __future__ import annotations

import math
import warnings
from typing import Any

import numpy as np

from ..errors import ModelError
from .base import ShapeFamily, as_abscissae, check_mode_count, parse_boundary

__all__ = ["StaticCorrection", "correction_count", "accepts_corrections"]

#: A correction shape whose part outside the span of the functions before it has a mass norm
#: below this fraction of its own is dependent and dropped.
DEPENDENCE = 1e-10

#: Polynomial coefficients (increasing powers of xi) of the correction shapes at the tip, by kind.
_TIP_SHAPES = {
    "transverse": ((0.0, 0.0, 1.5, -0.5), (0.0, 0.0, 1.0)),   # unit tip force, unit tip moment
    "torsion": ((0.0, 1.0),),                                  # unit tip torque
    "axial": ((0.0, 1.0),),                                    # unit tip axial force
}

#: What each correction shape is the static response to, by kind (for messages).
_LOADS = {"transverse": ("force", "moment"), "torsion": ("torque",), "axial": ("axial force",)}


def accepts_corrections(family: ShapeFamily, kind: str | None = None) -> bool:
    """Whether the static tip-load shapes are admissible for ``family``'s boundary.

    They are for a clamped root (bending) or a fixed or clamped root (torsion, axial) with a free
    tip; not for a pinned root, a held tip or a family whose boundary is unspecified (user
    expressions without ``boundary``). ``kind`` is the use of the family (``transverse``,
    ``torsion``, ``axial``), its own ``kind`` when omitted (user expressions serve any use).
    """
    kind = kind or family.kind
    if kind not in _TIP_SHAPES:
        return False
    try:
        root, tip = parse_boundary(family.boundary)
    except ModelError:
        return False
    roots = ("clamped",) if kind == "transverse" else ("clamped", "fixed")
    return root in roots and tip == "free"


def correction_count(kind: str, n: int) -> int:
    """Number of correction shapes a basis of ``n`` functions of ``kind`` gets for a tip load (at
    most ``n - 1``: the family's first function stays)."""
    return min(len(_TIP_SHAPES.get(kind, ())), n - 1)


class StaticCorrection(ShapeFamily):
    """A base family whose last functions are replaced by static correction shapes at the tip.

    Parameters
    ----------
    base : ShapeFamily
        The beam's family (its root clamped or fixed, its tip free: :func:`accepts_corrections`).
    n : int
        Number of functions of the basis (the beam's count in this direction).
    where : str, optional
        What the basis belongs to (``beams.B.shape_y``), named in the warning of a dropped shape.
    kind : str, optional
        The use of the basis, ``transverse``, ``torsion`` or ``axial``: the base family's ``kind``
        when omitted (a family of user expressions serves any use).
    """

    name = "static-correction"

    def __init__(self, base: ShapeFamily, n: int, where: str = "", kind: str | None = None):
        if not isinstance(base, ShapeFamily) or not accepts_corrections(base, kind):
            raise ModelError(where or "base", "a family with a clamped (or fixed) root and a free tip",
                             getattr(base, "name", base))
        n = check_mode_count(n)
        kind = kind or base.kind
        super().__init__({"base": base, "n": n, "kind": kind})
        self.base = base
        self.kind = kind
        self.boundary = base.boundary
        self.n = n
        self._base_count, self._coefficients = self._basis(where)

    @property
    def max_modes(self) -> int:
        return self.n

    @property
    def rounding_gain(self) -> float:
        """How much the basis amplifies the rounding of the base functions' values: the largest
        sum of the magnitudes of a function's coefficients (a correction shape nearly spanned by
        the modes is their small difference); :mod:`flexkane.modes.integrals` verifies its
        quadrature to ``1e-13`` times this."""
        return float(np.abs(self._coefficients).sum(axis=1).max())

    def __repr__(self) -> str:
        return f"StaticCorrection({self.base!r}, n={self.n})"

    # ------------------------------------------------------------------ construction
    def _candidates(self, xi: np.ndarray, deriv: int) -> np.ndarray:
        """Base functions ``1..base_count`` then the tip shapes: shape ``(base_count + k, m)``."""
        rows = [self.base.phi(xi, self._base_count, deriv)] if self._base_count else []
        for coefficients in _TIP_SHAPES[self.kind]:
            poly = np.polynomial.Polynomial(coefficients).deriv(deriv)
            rows.append(np.atleast_2d(poly(xi) * np.ones_like(xi)))
        return np.vstack(rows)

    def _basis(self, where: str) -> tuple[int, np.ndarray]:
        """The coefficients of the basis in the candidates (``n`` rows).

        Candidates in order: base functions ``1..n-k`` (kept as they are), the ``k`` tip shapes,
        then base functions ``n-k+1..n`` (taken only in place of dropped shapes); each one after
        the first ``n - k`` is made mass-orthogonal to the kept ones and mass-normalised.
        """
        from .integrals import gauss_legendre, quadrature_order

        used = correction_count(self.kind, self.n)
        limit = self.base.max_modes
        spare = self.n if limit is None else min(self.n, limit)
        self._base_count = spare
        x, w = gauss_legendre(quadrature_order(self.base, spare) + 8)
        values = self._candidates(x, 0)                         # (spare + k, N)

        def inner(a: np.ndarray, b: np.ndarray) -> float:
            # the mass inner product of two combinations, from their values: a combination that
            # nearly cancels keeps the rounding of its values, not that of the candidates' Gram matrix
            return float((a @ values) * w @ (b @ values))

        order = list(range(self.n - used)) + [spare + j for j in range(used)] \
            + list(range(self.n - used, spare))
        kept: list[np.ndarray] = []      # coefficient rows of the basis
        orthonormal: list[np.ndarray] = []   # a mass-orthonormal basis of their span
        for position, index in enumerate(order):
            if len(kept) == self.n:
                break
            e = np.zeros(len(values))
            e[index] = 1.0
            v = e.copy()
            for _ in range(2):                                  # Gram-Schmidt, twice
                for u in orthonormal:
                    v = v - inner(u, v) * u
            norm = math.sqrt(max(inner(v, v), 0.0))
            if norm <= math.sqrt(DEPENDENCE) * math.sqrt(inner(e, e)):
                if index >= spare:
                    load = _LOADS[self.kind][index - spare]
                    warnings.warn(f"{where or self.base.name}: the static correction shape of a unit tip "
                                  f"{load} is spanned by the functions before it (family {self.base.name!r}); "
                                  "dropped, the next function of the family takes its place", stacklevel=3)
                    continue
                raise ModelError(where or self.base.name, "linearly independent shape functions",
                                 f"function {index + 1} of family {self.base.name!r} depends on the others")
            v = v / norm
            v = v / math.sqrt(inner(v, v))                      # once more, from the values
            orthonormal.append(v)
            kept.append(e if position < self.n - used else v)
        if len(kept) < self.n:
            raise ModelError(where or self.base.name, f"{self.n} independent shape functions with the "
                             "static correction shapes", f"{len(kept)} (the family provides no more)")
        return spare, np.vstack(kept)

    # ------------------------------------------------------------------ contract
    def phi(self, xi: Any, n: int, deriv: int = 0) -> np.ndarray:
        """``d^k Phi_i / d xi^k`` of the first ``n`` functions of the basis; shape ``(n, len(xi))``."""
        x = as_abscissae(xi)
        deriv = self._check_deriv(deriv)
        n = self._check_n(n)
        return self._coefficients[:n] @ self._candidates(x, deriv)

    def quadrature_order(self, n: int) -> int:
        # the tip shapes are cubics at most: the base family's order covers their products
        return self.base.quadrature_order(self._base_count) + 4

    def corrections(self) -> int:
        """How many functions of the basis are correction shapes (not functions of the base)."""
        return int(np.count_nonzero(np.abs(self._coefficients[:, self._base_count:]).sum(axis=1)))
