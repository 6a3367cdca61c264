"""Modal fields: quantities that vary along a beam, as sums of known functions of x.

Along a beam, every kinematic quantity of eqs. 8.18-8.21 is a finite sum ``sum_a c_a(q, u, t) f_a(x)``
whose *atoms* ``f_a`` are fixed functions of x:

=========== ====================================== ===============================
atom        function of x                          origin
=========== ====================================== ===============================
``ONE``     1                                      rigid motion of the beam frame
``X``       x                                      position along the undeformed axis
``phi(i)``  Phi_i(x)                               transverse shape functions (8.15)
``psi(k)``  Psi_k(x)                               axial shape functions
``d(i,j)``  int_0^x Phi_i' Phi_j' dxi              foreshortening (geometric stiffening)
``dphi(i)`` Phi_i'(x)                              slope of the section (Rayleigh beams)
``theta(k)``Theta_k(x)                             torsion shape functions (3D)
=========== ====================================== ===============================

A spatial beam bends in two planes, each with its own shape family: its transverse atoms carry a
direction label, ``phi(i, "y")`` (deflection along the section's y axis) and ``phi(i, "z")``, and so
do its foreshortening atoms ``dfs(i, j, "y")``; the planar atoms have none. Atoms of different
labels are different functions with their own modal constants.

Integrating the product of two such sums over the beam, as eq. 8.22 does, needs only the integrals of
products of atoms, which are the modal constants (``m_B, e_B, I_B, E_i, F_i, G_ij``). So the
generalized inertia forces are obtained by algebra on the coefficients, with the constants as
symbols: no symbolic integration over x ever happens.

A rigid quantity is a field with the single atom ``ONE``. The angular velocity of the section of a
Rayleigh beam at x, ``omega_B + sum_i Phi_i'(x) q_i'``, is a scalar field of the atoms ``ONE`` and
``dphi(i)``; its products are integrated with the weight ``rho_I`` (the section's mass moment of
inertia per unit length) instead of ``rho``.
"""

from __future__ import annotations

from typing import Callable, Iterable

import sympy as sp

__all__ = ["Atom", "ONE", "X", "phi", "psi", "dfs", "dphi", "theta", "direction", "Field", "Vec", "vec", "rigid",
           "dot_fields", "Vec3", "vec3", "cross3", "vec3_map"]

#: An atom: a tuple whose first item names the kind (see the module docstring).
Atom = tuple
ONE: Atom = ("1",)
X: Atom = ("x",)


def phi(i: int, label: str | None = None) -> Atom:
    """Transverse shape function Phi_i (1-based, as in the chapter); ``label`` ``"y"`` or ``"z"``:
    of a spatial beam's family for that direction."""
    return ("phi", i) if label is None else ("phi", i, label)


def theta(k: int) -> Atom:
    """Torsion shape function Theta_k (1-based) of a spatial beam."""
    return ("theta", k)


def direction(atom: Atom) -> str | None:
    """The direction label of a transverse or foreshortening atom (None for planar atoms and others)."""
    if atom[0] in ("phi", "dphi") and len(atom) == 3:
        return atom[2]
    if atom[0] == "d" and len(atom) == 4:
        return atom[3]
    return None


def psi(k: int) -> Atom:
    """Axial shape function Psi_k (1-based)."""
    return ("psi", k)


def dfs(i: int, j: int, label: str | None = None) -> Atom:
    """Foreshortening function d_ij(x) = int_0^x Phi_i' Phi_j' (symmetric in i, j); ``label`` as
    for :func:`phi`."""
    return ("d", min(i, j), max(i, j)) if label is None else ("d", min(i, j), max(i, j), label)


def dphi(i: int, label: str | None = None) -> Atom:
    """Slope Phi_i'(x) [1/m] of transverse shape function i (1-based): the section's rotation;
    ``label`` as for :func:`phi`."""
    return ("dphi", i) if label is None else ("dphi", i, label)


def atom_order(atom: Atom) -> tuple:
    """A total order on atoms (for deterministic output)."""
    kinds = {"1": 0, "x": 1, "phi": 2, "psi": 3, "d": 4, "dphi": 5, "theta": 6}
    return (kinds[atom[0]],) + tuple(atom[1:])


class Field:
    """A sum ``sum_a coefficient_a * atom_a(x)`` with SymPy coefficients.

    Parameters
    ----------
    terms : dict of Atom to sympy.Expr, optional
        Coefficients by atom; zero coefficients are dropped.
    """

    __slots__ = ("terms",)

    def __init__(self, terms: dict | None = None):
        self.terms: dict[Atom, sp.Expr] = {}
        if terms:
            for atom, coeff in terms.items():
                coeff = sp.sympify(coeff)
                if coeff != 0:
                    self.terms[atom] = coeff

    # ---------------------------------------------------------------- algebra
    def __add__(self, other: "Field") -> "Field":
        out = dict(self.terms)
        for atom, coeff in other.terms.items():
            out[atom] = out.get(atom, 0) + coeff
        return Field(out)

    def __neg__(self) -> "Field":
        return Field({a: -c for a, c in self.terms.items()})

    def __sub__(self, other: "Field") -> "Field":
        return self + (-other)

    def scale(self, factor) -> "Field":
        """The field multiplied by an expression that does not depend on x."""
        factor = sp.sympify(factor)
        if factor == 0:
            return Field()
        return Field({a: factor * c for a, c in self.terms.items()})

    def map(self, function: Callable[[sp.Expr], sp.Expr]) -> "Field":
        """Apply ``function`` to every coefficient (differentiation, substitution, ...)."""
        return Field({a: function(c) for a, c in self.terms.items()})

    # ---------------------------------------------------------------- queries
    def is_zero(self) -> bool:
        return not self.terms

    def coefficient(self, atom: Atom) -> sp.Expr:
        return self.terms.get(atom, sp.Integer(0))

    def atoms(self) -> list[Atom]:
        return sorted(self.terms, key=atom_order)

    def evaluate(self, value_of: Callable[[Atom], sp.Expr]) -> sp.Expr:
        """The field at one station: ``sum_a c_a value_of(a)``."""
        return sp.Add(*[c * value_of(a) for a, c in self.items()])

    def items(self) -> Iterable[tuple[Atom, sp.Expr]]:
        for atom in self.atoms():
            yield atom, self.terms[atom]

    def __repr__(self) -> str:
        return "Field(" + ", ".join(f"{a}: {c}" for a, c in self.items()) + ")"


def rigid(expr) -> Field:
    """A field that does not vary along x."""
    return Field({ONE: expr})


#: A planar vector field: (component along the frame's x axis, component along its y axis).
Vec = tuple


def vec(x, y) -> Vec:
    """A planar vector of fields; plain expressions are taken as rigid fields."""
    return (x if isinstance(x, Field) else rigid(x), y if isinstance(y, Field) else rigid(y))


def vec_add(a: Vec, b: Vec) -> Vec:
    return (a[0] + b[0], a[1] + b[1])


def vec_map(a: Vec, function) -> Vec:
    return (a[0].map(function), a[1].map(function))


def cross_z(omega, a: Vec) -> Vec:
    """``omega k x a`` for a planar vector ``a``: ``(-omega a_y, omega a_x)``."""
    return (a[1].scale(-omega), a[0].scale(omega))


def rotate(a: Vec, angle) -> Vec:
    """Components of the same vector in a frame turned by ``-angle``.

    If ``a`` is expressed in frame A and frame C is turned by ``angle`` relative to A, the
    components in C are ``R(-angle) a``.
    """
    if angle == 0:
        return a
    c, s = sp.cos(angle), sp.sin(angle)
    return (a[0].scale(c) + a[1].scale(s), a[1].scale(c) - a[0].scale(s))


def dot_fields(a: Vec, b: Vec, integrate: Callable[[Field, Field], sp.Expr]) -> sp.Expr:
    """``integral a . b`` using ``integrate(f, g)`` for the product of two scalar fields."""
    return integrate(a[0], b[0]) + integrate(a[1], b[1])


#: A spatial vector field: components along a frame's x, y and z axes.
Vec3 = tuple


def vec3(x, y, z) -> Vec3:
    """A 3-vector of fields; plain expressions are taken as rigid fields."""
    return tuple(c if isinstance(c, Field) else rigid(c) for c in (x, y, z))


def vec3_map(a: Vec3, function) -> Vec3:
    return tuple(c.map(function) for c in a)


def cross3(omega: tuple, a: Vec3) -> Vec3:
    """``omega x a`` for a rigid 3-vector ``omega`` (expressions) and a vector field ``a``."""
    wx, wy, wz = omega
    return (a[2].scale(wy) - a[1].scale(wz), a[0].scale(wz) - a[2].scale(wx), a[1].scale(wx) - a[0].scale(wy))
