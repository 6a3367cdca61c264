"""Modal constants of one beam: the symbols that replace integrals over x, and their values.

The chapter defines, below eq. 8.22,

    m_B = int rho dx,  e_B = int x rho dx,  I_B = int x^2 rho dx,
    E_i = int Phi_i rho dx,  F_i = int x Phi_i rho dx,  G_ij = int Phi_i Phi_j rho dx,

and in eq. 8.32 ``H_ij = int EI Phi_i'' Phi_j'' dx``. For a Rayleigh beam (rotary inertia of the
sections, weight ``rho_I`` [kg m] instead of ``rho``) it adds

    Ir_B = int rho_I dx,  Er_i = int rho_I Phi_i' dx,  Gr_ij = int rho_I Phi_i' Phi_j' dx.

:class:`BeamConstants` hands out such symbols
for the integral over the beam of the product of any two atoms of :mod:`flexkane.kane.modal_field`
(and of single atoms, for distributed gravity), records which ones a derivation used, and computes
their values by Gauss-Legendre quadrature for given L [m], rho [kg/m], EI [N m^2].
"""

from __future__ import annotations

import sympy as sp

from ..model.values import GeneratedSymbol
from ..model.constant_names import MODAL_STEMS, generated_constant  # noqa: F401 - re-exported
from .modal_field import ONE, X, Atom, Field, atom_order

__all__ = ["BeamConstants", "generated_constant"]

def _idx(*indices: int) -> str:
    return "".join(str(i) for i in indices) if all(i < 10 for i in indices) else "_".join(map(str, indices))


class BeamConstants:
    """Symbols for the modal constants of one beam.

    Parameters
    ----------
    name : str
        Beam name; it labels the mass constants (``m_B``, ``e_B``, ``I_B`` for the chapter's beam B).
    label : str
        Label of the modal constants: ``""`` gives the chapter's ``E_1``, ``G_12``; a beam name
        gives ``E_arm_1``.
    """

    def __init__(self, name: str, label: str = ""):
        self.name = name
        self.label = label
        #: symbol -> specification used by :meth:`values`
        self.used: dict[sp.Symbol, tuple] = {}
        self._cache: dict[tuple, sp.Symbol] = {}

    # ------------------------------------------------------------------ naming
    def _symbol(self, spec: tuple, name: str) -> sp.Symbol:
        if spec not in self._cache:
            symbol = GeneratedSymbol(name, real=True)
            self._cache[spec] = symbol
            self.used[symbol] = spec
        return self._cache[spec]

    def _modal(self, stem: str, *indices: int) -> str:
        return f"{stem}_{self.label + '_' if self.label else ''}{_idx(*indices)}"

    def pair(self, a: Atom, b: Atom) -> sp.Symbol:
        """``int_0^L rho a(x) b(x) dx``."""
        a, b = sorted((a, b), key=atom_order)
        kinds = (a[0], b[0])
        if kinds == ("1", "1"):
            name = f"m_{self.name}"
        elif kinds == ("1", "x"):
            name = f"e_{self.name}"
        elif kinds == ("x", "x"):
            name = f"I_{self.name}"
        elif kinds == ("1", "phi"):
            name = self._modal("E", b[1])
        elif kinds == ("x", "phi"):
            name = self._modal("F", b[1])
        elif kinds == ("phi", "phi"):
            name = self._modal("G", a[1], b[1])
        elif kinds == ("1", "psi"):
            name = self._modal("A", b[1])
        elif kinds == ("x", "psi"):
            name = self._modal("Ax", b[1])
        elif kinds == ("phi", "psi"):
            name = self._modal("C", a[1], b[1])
        elif kinds == ("psi", "psi"):
            name = self._modal("AA", a[1], b[1])
        elif kinds == ("1", "d"):
            name = self._modal("D", *b[1:])
        elif kinds == ("x", "d"):
            name = self._modal("Dx", *b[1:])
        elif kinds == ("phi", "d"):
            name = self._modal("Dphi", *(b[1:] + a[1:]))
        elif kinds == ("psi", "d"):
            name = self._modal("Dpsi", *(b[1:] + a[1:]))
        else:  # ("d", "d")
            name = self._modal("DD", *(a[1:] + b[1:]))
        return self._symbol(("pair", a, b), name)

    def rotary(self, a: Atom, b: Atom) -> sp.Symbol:
        """``int_0^L rho_I a(x) b(x) dx`` for atoms ``ONE`` and ``dphi(i)`` (Rayleigh beam)."""
        a, b = sorted((a, b), key=atom_order)
        kinds = (a[0], b[0])
        if kinds == ("1", "1"):
            name = f"Ir_{self.name}"
        elif kinds == ("1", "dphi"):
            name = self._modal("Er", b[1])
        elif kinds == ("dphi", "dphi"):
            name = self._modal("Gr", a[1], b[1])
        else:
            raise ValueError(f"no rotary-inertia constant for the atoms {a!r}, {b!r}")
        return self._symbol(("rotary", a, b), name)

    def rotary_integrate(self, f: Field, g: Field) -> sp.Expr:
        """``int_0^L rho_I f(x) g(x) dx`` for two fields of the atoms ``ONE`` and ``dphi(i)``."""
        return sp.Add(*[ca * cb * self.rotary(a, b) for a, ca in f.items() for b, cb in g.items()])

    def rotary_integrate1(self, f: Field) -> sp.Expr:
        """``int_0^L rho_I f(x) dx``."""
        return sp.Add(*[c * self.rotary(ONE, a) for a, c in f.items()])

    # the spatial engine's calls for the same constants (a planar chain derived by the spatial engine:
    # its beams bend in the family y only, their sections turning about z)
    @staticmethod
    def _family_y(label: str) -> None:
        if label != "y":
            raise ValueError(f"a planar beam bends in the family y only (sections turning about z), not {label!r}")

    def section(self, axis: str, a: Atom, b: Atom) -> sp.Symbol:
        """:meth:`rotary` of the sections turning about z (``axis`` ``"y"``, the bending family)."""
        self._family_y(axis)
        return self.rotary(a, b)

    def section_integrate(self, axis: str, f: Field, g: Field) -> sp.Expr:
        """:meth:`rotary_integrate` (``axis`` as for :meth:`section`)."""
        self._family_y(axis)
        return self.rotary_integrate(f, g)

    def section_integrate1(self, axis: str, f: Field) -> sp.Expr:
        """:meth:`rotary_integrate1` (``axis`` as for :meth:`section`)."""
        self._family_y(axis)
        return self.rotary_integrate1(f)

    def bending_stiffness(self, i: int, j: int, label: str) -> sp.Symbol:
        """:meth:`stiffness` ``H_ij`` of the bending family ``label`` ``"y"``."""
        self._family_y(label)
        return self.stiffness(i, j)

    def single(self, a: Atom) -> sp.Symbol:
        """``int_0^L rho a(x) dx`` (equal to :meth:`pair` with ``ONE``)."""
        return self.pair(ONE, a)

    def integrate(self, f: Field, g: Field) -> sp.Expr:
        """``int_0^L rho f(x) g(x) dx`` for two fields."""
        terms = []
        for a, ca in f.items():
            for b, cb in g.items():
                terms.append(ca * cb * self.pair(a, b))
        return sp.Add(*terms)

    def integrate1(self, f: Field) -> sp.Expr:
        """``int_0^L rho f(x) dx``."""
        return sp.Add(*[c * self.single(a) for a, c in f.items()])

    def stiffness(self, i: int, j: int) -> sp.Symbol:
        """``H_ij = int_0^L EI Phi_i'' Phi_j'' dx`` [N/m], eq. 8.32."""
        i, j = min(i, j), max(i, j)
        return self._symbol(("H", i, j), self._modal("H", i, j))

    def axial_stiffness(self, k: int, l: int) -> sp.Symbol:
        """``int_0^L EA Psi_k' Psi_l' dx`` [N/m]."""
        k, l = min(k, l), max(k, l)
        return self._symbol(("HA", k, l), self._modal("HA", k, l))

    def station(self, atom: Atom, x: sp.Expr, text: str, deriv: int = 0) -> sp.Expr:
        """Value of an atom (or of its x-derivative) at the station ``x`` [m].

        Parameters
        ----------
        atom : Atom
        x : sympy.Expr
            The station as an expression of parameters.
        text : str
            Readable form of the station, used in the symbol name (``L/2``).
        deriv : int
            Order of the derivative with respect to x.
        """
        if atom == ONE:
            return sp.Integer(1) if deriv == 0 else sp.Integer(0)
        if atom == X:
            return x if deriv == 0 else (sp.Integer(1) if deriv == 1 else sp.Integer(0))
        stem = {"phi": "Phi", "psi": "Psi", "d": "d", "dphi": "Phi'"}[atom[0]] + "'" * deriv
        name = f"{self._modal(stem, *atom[1:])}({text})"
        return self._symbol(("station", atom, deriv, x), name)

    def load_integral(self, atom: Atom, profile: sp.Expr, label: str) -> sp.Symbol:
        """``int_0^L a(x) h(x) dx`` for the x-profile ``h`` of a distributed load [m * units of a * h].

        Parameters
        ----------
        atom : Atom
        profile : sympy.Expr
            ``h(x)``, an expression of ``x`` (:data:`flexkane.kane.distributed_loads.POSITION`) and
            parameter symbols, evaluated numerically for each parameter set.
        label : str
            Names the load and its profile in the symbol (``K_wind_y1_Phi1``).
        """
        stem = {"1": "1", "x": "x", "phi": "Phi", "psi": "Psi", "d": "d", "dphi": "dPhi"}[atom[0]]
        name = f"K_{label}_{stem}{_idx(*atom[1:]) if len(atom) > 1 else ''}"
        return self._symbol(("load", atom, profile), name)

    def shear_moment(self, kind: str, i: int, j: int = 0) -> sp.Symbol:
        """Constants of eq. 8.28 evaluated with the shape functions as given (notebook variant).

        ``kind``: ``"M0"`` for Phi_i''(0) [1/m^2], ``"V0"`` for Phi_i'''(0) [1/m^3], ``"J"`` for
        int Phi_i'''' dx, ``"Jx"`` for int x Phi_i'''' dx, ``"JPhi"`` for int Phi_j Phi_i'''' dx.
        """
        names = {"M0": f"{self._modal('Phi', i)}''(0)", "V0": f"{self._modal('Phi', i)}'''(0)",
                 "J": self._modal("J", i), "Jx": self._modal("Jx", i), "JPhi": self._modal("JPhi", j, i)}
        return self._symbol(("shear", kind, i, j), names[kind])

    # ------------------------------------------------------------------ numbers
    def values(self, *, L: float, rho: float, EI: float, family, n: int, EA: float | None = None,
               axial_family=None, n_axial: int = 0, station_values: dict | None = None,
               profiles: dict | None = None, rotary_inertia: float | None = None) -> dict:
        """Numeric value of every constant used.

        Parameters
        ----------
        L, rho, EI : float
            Length [m], mass per unit length [kg/m], flexural rigidity [N m^2].
        family : ShapeFamily
            Transverse shape functions (see :mod:`flexkane.modes`).
        n : int
            Number of transverse shape functions.
        EA : float, optional
            Axial stiffness [N].
        axial_family : ShapeFamily, optional
        n_axial : int
        station_values : dict, optional
            Numeric value [m] of each station expression used.
        profiles : dict, optional
            For each x-profile of a distributed load used, a function of x [m] (array (m,) to
            array (m,)) with the parameters' values substituted.
        rotary_inertia : float, optional
            Mass moment of inertia of the section per unit length ``rho_I`` [kg m] (Rayleigh
            beam), required when a rotary constant is used.

        Returns
        -------
        dict of sympy.Symbol to float
        """
        from .beam_quadrature import AtomEvaluator

        ev = AtomEvaluator(L=L, family=family, n=n, axial_family=axial_family, n_axial=n_axial)
        out = {}
        for symbol, spec in self.used.items():
            kind = spec[0]
            if kind == "pair":
                out[symbol] = rho * ev.integral(spec[1], spec[2])
            elif kind == "rotary":
                out[symbol] = rotary_inertia * ev.integral(spec[1], spec[2])
            elif kind == "H":
                out[symbol] = EI * ev.derivative_integral(("phi", spec[1]), ("phi", spec[2]), 2)
            elif kind == "HA":
                out[symbol] = EA * ev.derivative_integral(("psi", spec[1]), ("psi", spec[2]), 1)
            elif kind == "station":
                out[symbol] = ev.at(spec[1], float(station_values[spec[3]]), spec[2])
            elif kind == "load":
                out[symbol] = ev.profile_integral(spec[1], profiles[spec[2]])
            elif kind == "shear":
                out[symbol] = ev.shear_moment(spec[1], spec[2], spec[3])
            else:  # pragma: no cover - specs are made above
                raise AssertionError(spec)
        return {k: float(v) for k, v in out.items()}
