"""Modal constants of a spatial beam: two bending families, torsion and axial stretch.

A spatial beam's atoms (:mod:`flexkane.kane.modal_field`) carry the direction of the family they
come from: ``phi(i, "y")`` and ``phi(i, "z")`` are the i-th shape functions of the deflections along
the section's y and z axes, ``dfs(i, j, "y")`` their foreshortening functions, ``theta(k)`` the
torsion shape functions, ``psi(k)`` the axial ones. Their constants are named like the planar ones
with the direction in the index (``E_y1 = int rho Phi_1^y dx``, ``G_y1_z2``, ``DD_y11_z22``) and:

    Ip_B = int rho_Ip dx,  Et_k = int rho_Ip Theta_k dx,  Gt_kl = int rho_Ip Theta_k Theta_l dx,
    Irz_B = int rho_Iz dx,  Er_yi = int rho_Iz Phi_i^y' dx,  Gr_yi_yj = int rho_Iz Phi_i^y' Phi_j^y' dx
    (and Iry_B, Er_zi, Gr_zi_zj with rho_Iy and the z family: the Rayleigh beam's turning sections),
    H_yij = int EI_z Phi_i^y'' Phi_j^y'' dx,  H_zij = int EI_y Phi_i^z'' Phi_j^z'' dx,
    Kt_kl = int GJ Theta_k' Theta_l' dx,  HA_kl = int EA Psi_k' Psi_l' dx

(the deflection along y bends about the section's z axis, hence ``EI_z``). Values are computed by
Gauss-Legendre quadrature of an order verified for every family involved (twice that with
foreshortening atoms, as :mod:`flexkane.kane.beam_quadrature` does).
"""

from __future__ import annotations

import numpy as np
import sympy as sp

from .beam_constants import BeamConstants, _idx
from .beam_quadrature import AtomEvaluator, _leggauss
from .modal_field import ONE, Atom, Field, atom_order, direction, phi

__all__ = ["SpatialBeamConstants", "SpatialAtomEvaluator"]

#: Stem of the constant of a pair of atom kinds (sorted by :func:`atom_order`), as for planar beams.
_STEMS = {("1", "phi"): "E", ("x", "phi"): "F", ("phi", "phi"): "G", ("phi", "psi"): "C", ("1", "d"): "D",
          ("x", "d"): "Dx", ("phi", "d"): "Dphi", ("psi", "d"): "Dpsi", ("d", "d"): "DD"}


def _piece(atom: Atom) -> str:
    """Index text of an atom in a constant's name (``y1``, ``z12``, ``3``)."""
    label = direction(atom)
    return (label or "") + _idx(*[i for i in atom[1:] if isinstance(i, int)])


class SpatialBeamConstants(BeamConstants):
    """Symbols and values of the modal constants of one spatial beam (module docstring)."""

    def pair(self, a: Atom, b: Atom) -> sp.Symbol:
        """``int_0^L rho a(x) b(x) dx``."""
        if direction(a) is None and direction(b) is None:
            return super().pair(a, b)      # 1, x, psi: the planar names
        a, b = sorted((a, b), key=atom_order)
        kinds = (a[0], b[0])
        pieces = [_piece(atom) for atom in (a, b) if atom[0] not in ("1", "x")]
        stem = _STEMS[kinds]
        if kinds in (("phi", "d"), ("psi", "d")):    # named with the foreshortening atom first
            pieces = pieces[::-1]
        return self._symbol(("pair", a, b), f"{stem}_{self.label + '_' if self.label else ''}{'_'.join(pieces)}")

    def section(self, axis: str, a: Atom, b: Atom) -> sp.Symbol:
        """``int_0^L rho_J a(x) b(x) dx``: the sections' mass moment of inertia per length about
        the axis of a turn, ``axis`` ``"t"`` (the beam axis, ``rho_Ip``: atoms ``ONE``,
        ``theta(k)``), ``"y"`` (about z_p, turned by the slope of the y family: ``rho_Iz``, atoms
        ``ONE``, ``dphi(i, "y")``) or ``"z"`` (about y_p: ``rho_Iy``, ``dphi(j, "z")``)."""
        if axis == "t":
            return self.polar(a, b)
        a, b = sorted((a, b), key=atom_order)
        kinds = (a[0], b[0])
        if kinds == ("1", "1"):
            name = f"Ir{'z' if axis == 'y' else 'y'}_{self.name}"
        elif kinds == ("1", "dphi"):
            name = f"Er_{self.label + '_' if self.label else ''}{_piece(b)}"
        elif kinds == ("dphi", "dphi"):
            name = f"Gr_{self.label + '_' if self.label else ''}{_piece(a)}_{_piece(b)}"
        else:
            raise ValueError(f"no rotary-inertia constant for the atoms {a!r}, {b!r}")
        return self._symbol(("section", axis, a, b), name)

    def section_integrate(self, axis: str, f: Field, g: Field) -> sp.Expr:
        """``int_0^L rho_J f(x) g(x) dx`` (:meth:`section`)."""
        return sp.Add(*[ca * cb * self.section(axis, a, b) for a, ca in f.items() for b, cb in g.items()])

    def section_integrate1(self, axis: str, f: Field) -> sp.Expr:
        """``int_0^L rho_J f(x) dx`` (:meth:`section`)."""
        return sp.Add(*[c * self.section(axis, ONE, a) for a, c in f.items()])

    def polar(self, a: Atom, b: Atom) -> sp.Symbol:
        """``int_0^L rho_Ip a(x) b(x) dx`` for atoms ``ONE`` and ``theta(k)``."""
        a, b = sorted((a, b), key=atom_order)
        kinds = (a[0], b[0])
        if kinds == ("1", "1"):
            name = f"Ip_{self.name}"
        elif kinds == ("1", "theta"):
            name = self._modal("Et", b[1])
        elif kinds == ("theta", "theta"):
            name = self._modal("Gt", a[1], b[1])
        else:
            raise ValueError(f"no polar-inertia constant for the atoms {a!r}, {b!r}")
        return self._symbol(("polar", a, b), name)

    def bending_stiffness(self, i: int, j: int, label: str) -> sp.Symbol:
        """``H_<label>ij``: ``int EI_z Phi_i^y'' Phi_j^y'' dx`` (label y) or with ``EI_y`` and the z
        family (label z) [N/m]."""
        i, j = min(i, j), max(i, j)
        return self._symbol(("Hs", label, i, j), self._modal("H", f"{label}{_idx(i, j)}"))

    def torsion_stiffness(self, k: int, l: int) -> sp.Symbol:
        """``Kt_kl = int GJ Theta_k' Theta_l' dx`` [N m]."""
        k, l = min(k, l), max(k, l)
        return self._symbol(("Kt", k, l), self._modal("Kt", k, l))

    def shear_moment(self, kind: str, i: int, label: str, atom: Atom = ONE) -> sp.Symbol:
        """Constants of eq. 8.28 in the bending plane ``label`` (``y`` or ``z``;
        :mod:`flexkane.kane.spatial_beam_notebook`): ``"M0"`` for ``Phi_i''(0)`` [1/m^2], ``"V0"`` for
        ``Phi_i'''(0)`` [1/m^3]; ``"J"``, ``"Jx"``, ``"JPhi"`` for ``int a(x) Phi_i''''(x) dx`` with the
        atom ``a`` = 1, x or a shape function of either plane (``J_y1``, ``Jx_y1``, ``JPhi_z2_y1``)."""
        prefix = self.label + "_" if self.label else ""
        mode = _piece(phi(i, label))
        if kind in ("M0", "V0"):
            primes = "''" if kind == "M0" else "'''"
            return self._symbol(("shear", kind, i, label, ONE), f"Phi_{prefix}{mode}{primes}(0)")
        pieces = [_piece(atom), mode] if kind == "JPhi" else [mode]
        return self._symbol(("shear", kind, i, label, atom), f"{kind}_{prefix}{'_'.join(pieces)}")

    def _modal(self, stem: str, *indices) -> str:
        if all(isinstance(i, int) for i in indices):
            return super()._modal(stem, *indices)
        return f"{stem}_{self.label + '_' if self.label else ''}{''.join(map(str, indices))}"

    def station(self, atom: Atom, x: sp.Expr, text: str, deriv: int = 0) -> sp.Expr:
        """Value of an atom (or of its x-derivative) at the station ``x`` [m] (``Phi_y1(L)``,
        ``Theta_1'(L/2)``)."""
        if atom[0] in ("1", "x"):
            return super().station(atom, x, text, deriv)
        stem = {"phi": "Phi", "psi": "Psi", "d": "d", "theta": "Theta"}[atom[0]] + "'" * deriv
        name = f"{stem}_{self.label + '_' if self.label else ''}{_piece(atom)}({text})"
        return self._symbol(("station", atom, deriv, x), name)

    def load_integral(self, atom: Atom, profile: sp.Expr, label: str) -> sp.Symbol:
        """``int_0^L a(x) h(x) dx`` for the x-profile ``h`` of a distributed load
        (``K_<load>_<component><k>_Phi_y1``)."""
        if atom[0] in ("1", "x"):
            return super().load_integral(atom, profile, label)
        stem = {"phi": "Phi", "psi": "Psi", "d": "d", "theta": "Theta"}[atom[0]]
        return self._symbol(("load", atom, profile), f"K_{label}_{stem}_{_piece(atom)}")

    # ------------------------------------------------------------------ numbers
    def model_values(self, beam, fields, parameters, stations: dict | None = None,
                     profiles: dict | None = None, model=None) -> dict:
        """Numeric value of every constant used, for a beam of a model.

        Parameters
        ----------
        beam : flexkane.model.parts.Beam
            The spatial beam.
        fields : flexkane.model.field_values.FieldValues
            Values of the model's fields.
        parameters : dict
            The model's parameter values (numeric options of the shape families).
        stations : dict, optional
            Numeric value [m] of each station expression used.
        profiles : dict, optional
            For each x-profile of a distributed load used, a function of x [m] (array to array)
            with the parameters' values substituted.
        model : flexkane.model.model.Model, optional
            The model of the beam: with it, the beam's bases get their static correction shapes
            where it carries something at its tip (:func:`flexkane.modes.from_spec.beam_shape_family`).

        Returns
        -------
        dict of sympy.Symbol to float
        """
        from ..modes.from_spec import beam_shape_family, shape_family

        path = f"beams.{beam.name}"

        def number(key):
            value = getattr(beam, key)
            return None if value is None else fields.value(value, f"{path}.{key}")

        families = {}
        for label, count, key in (("y", beam.n_modes_y, "shape_y"), ("z", beam.n_modes_z, "shape_z"),
                                  ("t", beam.n_torsion, "torsion_shape"), ("a", beam.n_axial, "axial_shape")):
            if count:
                families[label] = ((beam_shape_family(model, beam, key, parameters) if model is not None
                                    else shape_family(getattr(beam, key), f"{path}.{key}", parameters)), count)
        ev = SpatialAtomEvaluator(number("L"), families)
        rho, rho_Ip = number("rho"), number("rho_Ip")
        rigidity = {"y": number("EI_z"), "z": number("EI_y")}
        rotary = {"y": number("rho_Iz"), "z": number("rho_Iy")}
        out = {}
        for symbol, spec in self.used.items():
            kind = spec[0]
            if kind == "pair":
                out[symbol] = rho * ev.integral(spec[1], spec[2])
            elif kind == "polar":
                out[symbol] = rho_Ip * ev.integral(spec[1], spec[2])
            elif kind == "section":
                out[symbol] = rotary[spec[1]] * ev.integral(spec[2], spec[3])
            elif kind == "Hs":
                label = spec[1]
                out[symbol] = rigidity[label] * ev.derivative_integral(("phi", spec[2], label),
                                                                       ("phi", spec[3], label), 2)
            elif kind == "Kt":
                out[symbol] = number("GJ") * ev.derivative_integral(("theta", spec[1]), ("theta", spec[2]), 1)
            elif kind == "station":
                out[symbol] = ev.values_at(spec[1], np.array([float(stations[spec[3]]) / ev.L]), spec[2])[0]
            elif kind == "load":
                out[symbol] = ev.profile_integral(spec[1], profiles[spec[2]])
            elif kind == "HA":
                out[symbol] = number("EA") * ev.derivative_integral(("psi", spec[1]), ("psi", spec[2]), 1)
            elif kind == "shear":
                out[symbol] = ev.shear_moment(*spec[1:])
            else:  # pragma: no cover - the spatial engine makes no other constants
                raise AssertionError(spec)
        return {k: float(v) for k, v in out.items()}


class SpatialAtomEvaluator:
    """Values and integrals of a spatial beam's atoms, each through the evaluator of its family.

    Parameters
    ----------
    L : float
        Beam length [m].
    families : dict
        ``label -> (ShapeFamily, n)`` for the labels ``y``, ``z`` (bending), ``t`` (torsion) and
        ``a`` (axial) that the beam has.
    """

    def __init__(self, L: float, families: dict):
        from ..modes.integrals import quadrature_order

        self.L = float(L)
        self.evaluators = {}
        order = 8
        for label, (family, n) in families.items():
            if label == "a":
                self.evaluators[label] = AtomEvaluator(L=L, family=family, n=n, axial_family=family, n_axial=n)
            else:
                self.evaluators[label] = AtomEvaluator(L=L, family=family, n=n)
            order = max(order, quadrature_order(family, n))
        self.order = order

    def values_at(self, atom: Atom, xi: np.ndarray, deriv: int = 0) -> np.ndarray:
        """Values of an atom (or of its x-derivative) at ``xi = x/L``, shape (len(xi),)."""
        kind = atom[0]
        xi = np.asarray(xi, dtype=float)
        if kind == "1":
            return np.ones_like(xi) if deriv == 0 else np.zeros_like(xi)
        if kind == "x":
            return xi * self.L if deriv == 0 else (np.ones_like(xi) if deriv == 1 else np.zeros_like(xi))
        if kind == "theta":
            return self.evaluators["t"].values_at(("phi", atom[1]), xi, deriv)
        if kind == "psi":
            return self.evaluators["a"].values_at(atom, xi, deriv)
        label = direction(atom)
        return self.evaluators[label].values_at(atom[:-1], xi, deriv)

    def _rule(self, fine: bool):
        xi, w = _leggauss(2 * self.order if fine else self.order)
        return xi, w * self.L

    def integral(self, a: Atom, b: Atom) -> float:
        """``int_0^L a(x) b(x) dx``."""
        xi, w = self._rule(a[0] == "d" or b[0] == "d")
        return float(np.sum(w * self.values_at(a, xi) * self.values_at(b, xi)))

    def profile_integral(self, a: Atom, profile) -> float:
        """``int_0^L a(x) h(x) dx`` for a function ``h`` of x [m] (a distributed load's profile),
        with twice the verified order, as for planar beams."""
        xi, w = self._rule(True)
        x = xi * self.L
        h = np.broadcast_to(np.asarray(profile(x), dtype=float), x.shape)
        return float(np.sum(w * self.values_at(a, xi) * h))

    def derivative_integral(self, a: Atom, b: Atom, deriv: int) -> float:
        """``int_0^L a^(k)(x) b^(k)(x) dx`` with k = ``deriv``."""
        xi, w = self._rule(False)
        return float(np.sum(w * self.values_at(a, xi, deriv) * self.values_at(b, xi, deriv)))

    def shear_moment(self, kind: str, i: int, label: str, atom: Atom) -> float:
        """Constants of eq. 8.28 (:meth:`SpatialBeamConstants.shear_moment`)."""
        mode = ("phi", i, label)
        if kind in ("M0", "V0"):
            return float(self.values_at(mode, np.zeros(1), 2 if kind == "M0" else 3)[0])
        xi, w = self._rule(False)
        return float(np.sum(w * self.values_at(atom, xi) * self.values_at(mode, xi, 4)))
