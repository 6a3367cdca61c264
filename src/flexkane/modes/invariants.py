"""Modal invariants of a beam: the integrals of its shape functions, as numeric arrays.

A flexible beam enters the equations of motion as a *modal body*: whatever the shape functions are
(an analytic family of :mod:`flexkane.modes`, modes computed by finite elements, a user's
polynomials), the equations need only integrals over the beam of products of them, weighted by the
section's properties. The chapter's (below eq. 8.22, and eq. 8.32)

    m_B = int rho dx,   e_B = int x rho dx,   I_B = int x^2 rho dx,
    E_i = int rho Phi_i dx,   F_i = int rho x Phi_i dx,   G_ij = int rho Phi_i Phi_j dx,
    H_ij = int EI Phi_i'' Phi_j'' dx,

and their counterparts for a spatial beam bending in two planes (a family per direction ``y``, ``z``;
``G^yz_ij = int rho Phi^y_i Phi^z_j dx`` couples them), for Rayleigh sections
(``Ir = int rho_I dx``, ``Er_i = int rho_I Phi_i' dx``, ``Gr_ij = int rho_I Phi_i' Phi_j' dx``), for
torsion (``Ip = int rho_Ip dx``, ``Et_k``, ``Gt_kl`` with ``Theta_k``, ``Kt_kl = int GJ Theta_k'
Theta_l' dx``), for axial stretch (``A_k = int rho Psi_k``, ``Ax_k``, ``AA_kl``, ``C_ik = int rho
Phi_i Psi_k``, ``HA_kl = int EA Psi_k' Psi_l' dx``) and for geometric stiffening, through the
foreshortening functions ``d_ij(x) = int_0^x Phi_i' Phi_j' ds`` (``D_ij = int rho d_ij``,
``Dx_ij = int rho x d_ij``, ``Dphi_kij = int rho Phi_k d_ij``, ``Dpsi_kij = int rho Psi_k d_ij``,
``DD_ijkl = int rho d_ij d_kl``) are here arrays indexed from 0 (the chapter's ``E_1`` is ``E[0]``).

:class:`ShapeBasis` is the contract a producer of shape functions meets (:meth:`ShapeBasis.of_family`
wraps an analytic family with its verified quadrature order); :func:`modal_invariants` computes the
arrays of one beam once per parameter set by Gauss-Legendre quadrature on ``[0, L]``, of the order
its bases verify (products of two shape functions or their derivatives to about 1e-13 relative),
twice that for products that involve the foreshortening functions (themselves quadratic in the
shape functions), whose values at the nodes come from a Gauss rule of the basis' order on each
``[0, x]``. Section properties are numbers or functions of x [m] (sections that vary along the
beam).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable, Union

import numpy as np

from ..errors import ModelError
from .integrals import gauss_legendre, quadrature_order

__all__ = ["ShapeBasis", "ModalInvariants", "modal_invariants", "Section"]

#: A section property: a number, or a vectorised function of x [m] (shape (N,) to (N,)).
Section = Union[float, Callable[[np.ndarray], np.ndarray]]


@dataclass(frozen=True)
class ShapeBasis:
    """``n`` shape functions of ``xi = x / L`` on ``[0, 1]``, from any producer.

    Attributes
    ----------
    n : int
        Number of functions.
    values : callable
        ``values(xi, deriv)``: the functions (``deriv = 0``) or their derivatives of order
        ``deriv`` with respect to ``xi``, at the abscissae ``xi`` (shape (N,)); shape (n, N).
    order : int
        A Gauss-Legendre order that integrates the products of two functions and of their first
        and second derivatives on ``[0, 1]`` to the accuracy wanted.
    """

    n: int
    values: Callable[[np.ndarray, int], np.ndarray]
    order: int

    @classmethod
    def of_family(cls, family, n: int) -> "ShapeBasis":
        """The first ``n`` functions of a :class:`~flexkane.modes.base.ShapeFamily`, with the
        quadrature order :func:`flexkane.modes.integrals.quadrature_order` verifies for them."""
        return cls(int(n), lambda xi, deriv: family.phi(xi, int(n), deriv), quadrature_order(family, int(n)))


def _section(value: Section | None, x: np.ndarray, name: str) -> np.ndarray:
    if value is None:
        raise ModelError(name, "a number or a function of x for an invariant that needs it", None)
    if callable(value):
        out = np.broadcast_to(np.asarray(value(x), dtype=float), x.shape)
    else:
        out = np.full(x.shape, float(value))
    if not np.all(np.isfinite(out)):
        raise ModelError(name, "finite values along the beam", value)
    return out


@dataclass
class _Rule:
    """Nodes ``x`` [m], ``xi = x / L`` and weights [m] of a Gauss-Legendre rule on [0, L]."""

    xi: np.ndarray
    x: np.ndarray
    w: np.ndarray


@dataclass
class ModalInvariants:
    """The invariants of one beam as numeric arrays (module docstring); computed on first use.

    Bending families are keyed by their direction label (``"y"``, ``"z"`` for a spatial beam, any
    label for a planar one, e.g. ``""``); arrays over two families are keyed by both labels in the
    order of their axes. Indices are 0-based. Units: ``rho`` [kg/m], shape functions dimensionless,
    derivatives with respect to x [1/m per order].

    Attributes
    ----------
    L : float
        Length [m].
    bending : dict of str to ShapeBasis
        Transverse shape functions per direction.
    torsion : ShapeBasis or None
    axial : ShapeBasis or None
    sections : dict of str to Section
        Section properties by name: ``rho`` [kg/m]; ``EI`` per direction label as ``"EI:<label>"``
        [N m^2] (for a spatial beam the deflection along y bends about z: ``"EI:y"`` is EI_z);
        ``"rho_I:<label>"`` [kg m] (the sections' rotary inertia turned by that direction's
        slope), ``rho_Ip`` [kg m], ``GJ`` [N m^2], ``EA`` [N].
    """

    L: float
    bending: dict
    torsion: ShapeBasis | None = None
    axial: ShapeBasis | None = None
    sections: dict = field(default_factory=dict)
    _cache: dict = field(default_factory=dict, repr=False)

    def __post_init__(self):
        self.L = float(self.L)
        if not (self.L > 0 and np.isfinite(self.L)):
            raise ModelError("L", "a positive finite length [m]", self.L)
        bases = [*self.bending.values(), self.torsion, self.axial]
        self.order = max([8] + [b.order for b in bases if b is not None and b.n])

    # ------------------------------------------------------------------ quadrature
    def _rule(self, fine: bool) -> _Rule:
        key = ("rule", fine)
        if key not in self._cache:
            xi, w = gauss_legendre(2 * self.order if fine else self.order)
            self._cache[key] = _Rule(xi, xi * self.L, w * self.L)
        return self._cache[key]

    def _weight(self, name: str, fine: bool = False) -> np.ndarray:
        rule = self._rule(fine)
        return rule.w * _section(self.sections.get(name), rule.x, name)

    def _values(self, group: tuple, fine: bool, deriv: int = 0) -> np.ndarray:
        """Values at the nodes of a group of functions, shape (k, N) (d: (n, n, N)).

        ``group``: ``("1",)``, ``("x",)``, ``("phi", label)``, ``("dphi", label)``,
        ``("d", label)``, ``("theta",)``, ``("psi",)``; ``deriv`` differentiates with respect to x.
        """
        key = ("values", group, fine, deriv)
        if key in self._cache:
            return self._cache[key]
        rule = self._rule(fine)
        kind = group[0]
        if kind == "1":
            out = (np.ones_like(rule.xi) if deriv == 0 else np.zeros_like(rule.xi))[None, :]
        elif kind == "x":
            out = (rule.x if deriv == 0 else np.ones_like(rule.xi) if deriv == 1 else np.zeros_like(rule.xi))[None, :]
        elif kind in ("phi", "dphi"):
            d = deriv + (kind == "dphi")
            out = np.asarray(self.bending[group[1]].values(rule.xi, d), dtype=float) / self.L ** d
        elif kind == "theta":
            out = np.asarray(self.torsion.values(rule.xi, deriv), dtype=float) / self.L ** deriv
        elif kind == "psi":
            out = np.asarray(self.axial.values(rule.xi, deriv), dtype=float) / self.L ** deriv
        elif kind == "d":
            if deriv:
                raise ValueError("the foreshortening functions are used without derivatives")
            out = self._foreshortening(self.bending[group[1]], rule.xi)
        else:
            raise ValueError(f"no group of functions {group!r}")
        self._cache[key] = out
        return out

    def _foreshortening(self, basis: ShapeBasis, xi: np.ndarray) -> np.ndarray:
        """``d_ij(x) = int_0^x Phi_i' Phi_j' ds`` at ``x = xi L`` [1/m], shape (n, n, len(xi))."""
        t, w = gauss_legendre(basis.order)
        nodes = (xi[:, None] * t[None, :]).ravel()
        slope = np.asarray(basis.values(nodes, 1), dtype=float).reshape(basis.n, xi.size, t.size)
        return np.einsum("ipk,jpk,k->ijp", slope, slope, w) * xi / self.L

    def integral(self, weight: str, *groups, deriv: int = 0) -> np.ndarray:
        """``int_0^L w a b dx`` (or ``int_0^L w a dx``) for all members of one or two groups.

        Parameters
        ----------
        weight : str
            Name of the section property ``w`` (:class:`ModalInvariants`).
        *groups : tuple
            One or two groups of functions: ``("1",)``, ``("x",)`` [m], ``("phi", label)``,
            ``("dphi", label)`` [1/m], ``("d", label)`` [1/m], ``("theta",)``, ``("psi",)``.
        deriv : int
            Order of the x-derivative taken of every function (2: bending stiffness).

        Returns
        -------
        numpy.ndarray
            Read-only; one axis per index of the groups' members (none for ``1`` and ``x``,
            two for ``d``), e.g. shape (n_a, n_a, n_b, n_b) for ``d`` with ``d``.
        """
        key = ("integral", weight, groups, deriv)
        if key in self._cache:
            return self._cache[key]
        fine = any(g[0] == "d" for g in groups)
        w = self._weight(weight, fine)
        values = [self._values(g, fine, deriv) for g in groups]
        letters = iter("abcdefgh")
        subscripts = ["".join(next(letters) for _ in range(v.ndim - 1)) for v in values]
        out = np.einsum(",".join(s + "z" for s in subscripts) + ",z->" + "".join(subscripts), *values, w)
        starts = np.cumsum([0] + [len(s) for s in subscripts])
        rigid = [int(start) for start, g in zip(starts, groups) if g[0] in ("1", "x")]
        out = np.array(out.squeeze(axis=tuple(rigid)) if rigid else out)
        out.flags.writeable = False
        self._cache[key] = out
        return out

    # ------------------------------------------------------------------ the chapter's invariants
    @property
    def m(self) -> float:
        """``m_B = int rho dx`` [kg]."""
        return float(self.integral("rho", ("1",)).reshape(()))

    @property
    def e(self) -> float:
        """``e_B = int rho x dx`` [kg m]."""
        return float(self.integral("rho", ("x",)).reshape(()))

    @property
    def I(self) -> float:  # noqa: E743 - the chapter's name
        """``I_B = int rho x^2 dx`` [kg m^2]."""
        return float(self.integral("rho", ("x",), ("x",)).reshape(()))

    def E(self, label) -> np.ndarray:
        """``E_i = int rho Phi_i dx`` [kg], shape (n,)."""
        return self.integral("rho", ("phi", label))

    def F(self, label) -> np.ndarray:
        """``F_i = int rho x Phi_i dx`` [kg m], shape (n,)."""
        return self.integral("rho", ("x",), ("phi", label))

    def G(self, label, other=None) -> np.ndarray:
        """``G_ij = int rho Phi^a_i Phi^b_j dx`` [kg], shape (n_a, n_b) (``b = a`` by default)."""
        return self.integral("rho", ("phi", label), ("phi", label if other is None else other))

    def H(self, label) -> np.ndarray:
        """``H_ij = int EI Phi_i'' Phi_j'' dx`` [N/m], shape (n, n), with the section property
        ``"EI:<label>"``."""
        return self.integral(f"EI:{label}", ("phi", label), ("phi", label), deriv=2)

    def Ir(self, label) -> float:
        """``Ir = int rho_I dx`` [kg m^2] with ``"rho_I:<label>"``."""
        return float(self.integral(f"rho_I:{label}", ("1",)).reshape(()))

    def Er(self, label) -> np.ndarray:
        """``Er_i = int rho_I Phi_i' dx`` [kg m], shape (n,)."""
        return self.integral(f"rho_I:{label}", ("dphi", label))

    def Gr(self, label) -> np.ndarray:
        """``Gr_ij = int rho_I Phi_i' Phi_j' dx`` [kg], shape (n, n)."""
        return self.integral(f"rho_I:{label}", ("dphi", label), ("dphi", label))

    @property
    def Ip(self) -> float:
        """``Ip = int rho_Ip dx`` [kg m^2]."""
        return float(self.integral("rho_Ip", ("1",)).reshape(()))

    @property
    def Et(self) -> np.ndarray:
        """``Et_k = int rho_Ip Theta_k dx`` [kg m], shape (n_t,)."""
        return self.integral("rho_Ip", ("theta",))

    @property
    def Gt(self) -> np.ndarray:
        """``Gt_kl = int rho_Ip Theta_k Theta_l dx`` [kg m], shape (n_t, n_t)."""
        return self.integral("rho_Ip", ("theta",), ("theta",))

    @property
    def Kt(self) -> np.ndarray:
        """``Kt_kl = int GJ Theta_k' Theta_l' dx`` [N m], shape (n_t, n_t)."""
        return self.integral("GJ", ("theta",), ("theta",), deriv=1)

    @property
    def A(self) -> np.ndarray:
        """``A_k = int rho Psi_k dx`` [kg], shape (n_a,)."""
        return self.integral("rho", ("psi",))

    @property
    def Ax(self) -> np.ndarray:
        """``Ax_k = int rho x Psi_k dx`` [kg m], shape (n_a,)."""
        return self.integral("rho", ("x",), ("psi",))

    @property
    def AA(self) -> np.ndarray:
        """``AA_kl = int rho Psi_k Psi_l dx`` [kg], shape (n_a, n_a)."""
        return self.integral("rho", ("psi",), ("psi",))

    @property
    def HA(self) -> np.ndarray:
        """``HA_kl = int EA Psi_k' Psi_l' dx`` [N/m], shape (n_a, n_a)."""
        return self.integral("EA", ("psi",), ("psi",), deriv=1)

    def C(self, label) -> np.ndarray:
        """``C_ik = int rho Phi_i Psi_k dx`` [kg], shape (n, n_a)."""
        return self.integral("rho", ("phi", label), ("psi",))

    def D(self, label) -> np.ndarray:
        """``D_ij = int rho d_ij dx`` [kg/m], shape (n, n)."""
        return self.integral("rho", ("d", label))

    def Dx(self, label) -> np.ndarray:
        """``Dx_ij = int rho x d_ij dx`` [kg], shape (n, n)."""
        return self.integral("rho", ("x",), ("d", label))

    def Dphi(self, label, of=None) -> np.ndarray:
        """``Dphi_kij = int rho Phi^b_k d^a_ij dx`` [kg/m] with ``a = label``, ``b = of`` (default
        ``a``), shape (n_b, n_a, n_a)."""
        return self.integral("rho", ("phi", label if of is None else of), ("d", label))

    def Dpsi(self, label) -> np.ndarray:
        """``Dpsi_kij = int rho Psi_k d_ij dx`` [kg/m], shape (n_a, n, n)."""
        return self.integral("rho", ("psi",), ("d", label))

    def DD(self, label, other=None) -> np.ndarray:
        """``DD_ijkl = int rho d^a_ij d^b_kl dx`` [kg/m^2], shape (n_a, n_a, n_b, n_b)."""
        return self.integral("rho", ("d", label), ("d", label if other is None else other))

    def at(self, group: tuple, x: float, deriv: int = 0) -> np.ndarray:
        """Values of a group of functions (the groups of :meth:`integral`) at the station ``x`` [m], shape (k,)
        (``d``: (n, n))."""
        xi = np.array([float(x) / self.L])
        kind = group[0]
        if kind == "d":
            return self._foreshortening(self.bending[group[1]], np.clip(xi, 0.0, 1.0))[..., 0]
        basis = {"phi": lambda: self.bending[group[1]], "theta": lambda: self.torsion,
                 "psi": lambda: self.axial}[kind]()
        return np.asarray(basis.values(xi, deriv), dtype=float)[:, 0] / self.L ** deriv


def modal_invariants(L: float, bending: dict, *, torsion: ShapeBasis | None = None,
                     axial: ShapeBasis | None = None, **sections: Section) -> ModalInvariants:
    """The invariants of one beam (:class:`ModalInvariants`), each array computed on first use.

    Parameters
    ----------
    L : float
        Length [m].
    bending : dict of str to ShapeBasis
        Transverse shape functions per direction label.
    torsion, axial : ShapeBasis, optional
        Torsion and axial shape functions.
    **sections : float or callable
        Section properties by name (:class:`ModalInvariants`); ``"EI:<label>"`` and
        ``"rho_I:<label>"`` are passed with ``**{"EI:y": ...}``.

    Returns
    -------
    ModalInvariants
    """
    return ModalInvariants(L, dict(bending), torsion, axial, dict(sections))
