"""Modal sums as one node of the equations: ``sum_i A_i a_i`` and ``sum_ij A_ij a_i b_j``.

Integrating the product of two modal fields (:mod:`flexkane.kane.modal_field`) over a beam gives, for
each pair of families of atoms (the bending functions of one direction, the torsion or the axial
functions, the slopes of a Rayleigh beam's sections), a double sum of modal constants times the
fields' coefficients: ``sum_ij G_ij a_i b_j`` with ``a_i`` the coefficient of ``Phi_i`` in one field
and ``b_j`` that of ``Phi_j`` in the other, or ``sum_i E_i a_i`` against the rigid atom. Written out
term by term that is ``n^2`` (``n``) terms for each entry of the equations that meets the beam, and
every mode adds code that the compiler must translate. :class:`ModalSum` keeps such a sum as one node
of the expression: its array of constants (the same symbols as the written-out terms, so the values
and the constants vector are unchanged), and its vectors of coefficients (tuples of expressions).

* Derivatives act on the vectors (the constants do not depend on q, u or t): ``d/ds sum A a b =
  sum A a' b + sum A a b'``, so the derivation's chain rule (:mod:`flexkane.kane.intermediates`) goes
  through.
* Common-subexpression elimination shares a vector, and an array, among the sums that use it: a
  beam's vector of coefficients is computed once per evaluation.
* The generated Numba code evaluates the sum by a loop (:mod:`flexkane.numerics.modal_loops`): its size does not
  grow with the number of terms, only with the length of the vectors it builds.
* Printed (``str``, LaTeX), a sum keeps the chapter's indexed form, ``sum_{i,j} G_ij a_i b_j``.

:class:`IndexedBeamConstants` are the modal constants of a spatial beam whose integrals give modal
sums where a family contributes at least :data:`MODAL_SUM_MIN_ATOMS` atoms to a field, and are
written out term by term below that (built-in models with two modes per plane keep their equations
unchanged); the foreshortening functions of geometric stiffening from :data:`MODAL_SUM_MIN_STIFFENING`
pairs.
"""

from __future__ import annotations

import re

import sympy as sp
from sympy.core.symbol import Str
from sympy.printing.precedence import PRECEDENCE

from .modal_field import Atom, Field, direction
from .spatial_beam_constants import SpatialBeamConstants

__all__ = ["ModalSum", "modal_sum", "IndexedBeamConstants", "MODAL_SUM_MIN_ATOMS", "written_out_sums",
           "atom_family", "contract", "modal_dot", "evaluate"]

#: A family that brings at least this many atoms to a field is integrated into modal sums.
MODAL_SUM_MIN_ATOMS = 3
#: A modal sum of fewer terms is written out: the call of a loop costs more than a few products
#: (one evaluation of the 3D arm with 8 modes per plane: 3.36 us with every family's sums as loops,
#: rank-one sums of 8 terms among them, against 2.53 us written out).
MODAL_SUM_MIN_TERMS = 12
#: The same for the foreshortening functions d_ij of geometric stiffening (pairs i <= j: 6 are
#: those of three modes; two modes, as the built-in rotor blade has, stay written out).
MODAL_SUM_MIN_STIFFENING = 6

_INDICES = "ijklmn"


class ModalSum(sp.Expr):
    """``sum_{i1..ir} A[i1, .., ir] v1[i1] ... vr[ir]`` for r = 1 or 2 (module docstring).

    Arguments (SymPy ``args``): ``name`` (:class:`sympy.core.symbol.Str`, the array's printed name),
    ``entries`` (a Tuple of the array's entries, row-major), ``shape`` (a Tuple of Integers) and one
    Tuple of expressions per axis (the vectors). Make them with :func:`modal_sum`.
    """

    is_commutative = True
    #: Printed as a sum: parenthesized in products and powers, by every printer.
    precedence = PRECEDENCE["Add"]

    def __new__(cls, *args):
        # every entry and coefficient a number (values substituted): the number itself
        if all(e.is_Number for part in (args[1], *args[3:]) for e in part):
            return _terms(args[1], tuple(int(k) for k in args[2]), args[3:])
        return super().__new__(cls, *args)

    def _eval_evalf(self, prec):
        return self.written_out().evalf(prec)

    @property
    def name(self) -> str:
        return self.args[0].name

    @property
    def entries(self) -> sp.Tuple:
        return self.args[1]

    @property
    def shape(self) -> tuple:
        return tuple(int(s) for s in self.args[2])

    @property
    def vectors(self) -> tuple:
        return self.args[3:]

    def _eval_derivative(self, s):
        if s in self.entries.free_symbols:
            raise ValueError(f"the entries of the modal sum {self.name} depend on {s}")
        terms = []
        for k, vector in enumerate(self.vectors):
            rate = [sp.diff(e, s) for e in vector]
            if any(r != 0 for r in rate):
                vectors = list(self.vectors)
                vectors[k] = rate
                terms.append(modal_sum(self.name, self.entries, self.shape, *vectors))
        return sp.Add(*terms)

    def written_out(self) -> sp.Expr:
        """The sum term by term."""
        return _terms(self.entries, self.shape, self.vectors)

    def _sympystr(self, printer):
        idx = _INDICES[:len(self.vectors)]
        vectors = " ".join(f"[{', '.join(printer.doprint(e) for e in v)}]_{i}" for i, v in zip(idx, self.vectors))
        return f"Sum_{''.join(idx)}({self.name}_{''.join(idx)} {vectors})"

    def _latex(self, printer):
        idx = _INDICES[:len(self.vectors)]
        stem, _, label = self.name.partition("_")
        sub = (label.replace("_", ",") + "," if label else "") + "".join(idx)
        vectors = r" \, ".join(r"\left(" + ", ".join(printer.doprint(e) for e in v) + r"\right)_{" + i + "}"
                               for i, v in zip(idx, self.vectors))
        return r"\sum_{" + ",".join(idx) + "} " + f"{stem}_{{{sub}}}" + r" \, " + vectors

    def _pythoncode(self, printer):
        """A loop (:mod:`flexkane.numerics.modal_loops`) for a printer that sets ``modal_loops``, else the terms."""
        if not getattr(printer, "modal_loops", False):
            return printer._print(self.written_out())
        entries = _tuple(printer._print(e) for e in self.entries)
        vectors = ", ".join(_tuple(printer._print(e) for e in v) for v in self.vectors)
        return f"modal_sum{len(self.vectors)}({entries}, {vectors})"

    def _numpycode(self, printer):
        return printer._print(self.written_out())

    def _ccode(self, printer):
        return printer._print(self.written_out())


def _terms(entries, shape, vectors) -> sp.Expr:
    """``sum A v`` (rank 1) or ``sum A a b`` (rank 2) term by term."""
    if len(vectors) == 1:
        return sp.Add(*[a * e for a, e in zip(entries, vectors[0])])
    (n, m), (a, b) = shape, vectors
    return sp.Add(*[entries[i * m + j] * a[i] * b[j] for i in range(n) for j in range(m)])


def _tuple(texts) -> str:
    texts = list(texts)
    return "(" + ", ".join(texts) + ("," if len(texts) == 1 else "") + ")"


def modal_sum(name: str, entries, shape, *vectors) -> sp.Expr:
    """A :class:`ModalSum`; 0 when a vector is zero, a row (column) when a vector has one term, the
    terms when there are fewer than :data:`MODAL_SUM_MIN_TERMS`.

    Parameters
    ----------
    name : str
        The array's printed name (``G_y_z``).
    entries : sequence of sympy.Expr
        The array's entries, row-major, ``prod(shape)`` of them.
    shape : sequence of int
        ``(n,)`` or ``(n, m)``.
    *vectors : sequence of sympy.Expr
        One per axis, of the axis' length.
    """
    shape = tuple(int(s) for s in shape)
    vectors = [sp.Tuple(*v) for v in vectors]
    if len(shape) != len(vectors) or len(shape) not in (1, 2) \
            or any(len(v) != s for v, s in zip(vectors, shape)) or len(entries) != sp.prod(shape):
        raise ValueError(f"modal sum {name}: shape {shape}, vectors of lengths {[len(v) for v in vectors]}, "
                         f"{len(entries)} entries")
    if any(all(e == 0 for e in v) for v in vectors):
        return sp.Integer(0)
    for axis, v in enumerate(vectors):    # a vector of one term picks a row (column) of the array
        nonzero = [k for k, e in enumerate(v) if e != 0]
        if len(nonzero) == 1 and len(v) > 1:
            k = nonzero[0]
            if len(shape) == 1:
                return v[k] * entries[k]
            n, m = shape
            picked = [entries[k * m + j] for j in range(m)] if axis == 0 else [entries[i * m + k] for i in range(n)]
            return v[k] * modal_sum(name, picked, (len(picked),), vectors[1 - axis])
    if len(entries) < MODAL_SUM_MIN_TERMS:    # a short sum is cheaper written out than called as a loop
        return _terms(entries, shape, vectors)
    return ModalSum(Str(name), sp.Tuple(*entries), sp.Tuple(*shape), *vectors)


def written_out_sums(expr):
    """``expr`` with every :class:`ModalSum` written out term by term."""
    sums = {s: s.written_out() for s in expr.atoms(ModalSum)}
    return expr.xreplace(sums) if sums else expr


def atom_family(atom: Atom):
    """The family an atom belongs to for modal sums (None: a rigid atom, written out)."""
    if atom[0] in ("phi", "dphi", "d"):
        return atom[0], direction(atom)
    if atom[0] in ("theta", "psi"):
        return (atom[0],)
    return None


def _least(family) -> int:
    """Fewest atoms of a family in a field that make a modal sum: :data:`MODAL_SUM_MIN_ATOMS`, and
    for the foreshortening functions ``d_ij`` (i <= j) as many as three modes give
    (:data:`MODAL_SUM_MIN_STIFFENING` pairs)."""
    return MODAL_SUM_MIN_STIFFENING if family[0] == "d" else MODAL_SUM_MIN_ATOMS


_KINDS = ("phi", "dphi", "d", "theta", "psi")


def _families(f: Field) -> list[tuple[object, list[tuple[Atom, sp.Expr]]]]:
    """The field's atoms by family (each rigid atom on its own), in atom order."""
    out: dict = {}
    for atom, coeff in f.items():
        family = atom_family(atom)
        out.setdefault(family if family is not None else atom, []).append((atom, coeff))
    return list(out.items())


def _name(symbol: sp.Expr) -> str:
    """The printed name of an array from that of its first entry (``G_y1_z2`` -> ``G_y_z``)."""
    return re.sub(r"\d+", "", getattr(symbol, "name", "A")).rstrip("_")


def contract(f: Field, g: Field, constant) -> sp.Expr:
    """``int w f g dx`` with ``constant(a, b)`` the integral of a pair of atoms (module docstring)."""
    terms = []
    for family_f, fa in _families(f):
        for family_g, gb in _families(g):
            big_f = isinstance(family_f[0], str) and family_f[0] in _KINDS and len(fa) >= _least(family_f)
            big_g = isinstance(family_g[0], str) and family_g[0] in _KINDS and len(gb) >= _least(family_g)
            if not (big_f or big_g):
                terms += [ca * cb * constant(a, b) for a, ca in fa for b, cb in gb]
                continue
            if big_f and big_g:
                entries = [constant(a, b) for a, _ in fa for b, _ in gb]
                terms.append(modal_sum(_name(entries[0]), entries, (len(fa), len(gb)),
                                       [c for _, c in fa], [c for _, c in gb]))
                continue
            long, short = (fa, gb) if big_f else (gb, fa)
            for b, cb in short:
                entries = [constant(a, b) for a, _ in long]
                terms.append(cb * modal_sum(_name(entries[0]), entries, (len(long),), [c for _, c in long]))
    return sp.Add(*terms)


def modal_dot(entries, vector) -> sp.Expr:
    """``sum_i A_i v_i``: a :class:`ModalSum` of at least :data:`MODAL_SUM_MIN_ATOMS` terms, else written
    out (``entries``: modal constants, e.g. a row of ``H``; ``vector``: the coefficients)."""
    entries, vector = list(entries), list(vector)
    if len(entries) < MODAL_SUM_MIN_ATOMS:
        return sp.Add(*[a * v for a, v in zip(entries, vector)])
    return modal_sum(_name(entries[0]), entries, (len(entries),), vector)


def evaluate(f: Field, value_of) -> sp.Expr:
    """The field at one station, ``sum_a c_a value_of(a)``, a family of at least
    :data:`MODAL_SUM_MIN_ATOMS` atoms as a :class:`ModalSum` of the atoms' values there."""
    terms = []
    for family, atoms in _families(f):
        if family[0] == "d" and len(atoms) < MODAL_SUM_MIN_STIFFENING:
            terms += [value_of(a) * c for a, c in atoms]
        else:
            terms.append(modal_dot([value_of(a) for a, _ in atoms], [c for _, c in atoms]))
    return sp.Add(*terms)


class IndexedBeamConstants(SpatialBeamConstants):
    """The modal constants of a spatial beam, its integrals of fields in modal sums (module
    docstring); names and values of the constants are those of :class:`SpatialBeamConstants`."""

    def integrate(self, f: Field, g: Field) -> sp.Expr:
        """``int_0^L rho f(x) g(x) dx``."""
        return contract(f, g, self.pair)

    def integrate1(self, f: Field) -> sp.Expr:
        """``int_0^L rho f(x) dx``."""
        from .modal_field import ONE

        return contract(Field({ONE: 1}), f, self.pair)

    def section_integrate(self, axis: str, f: Field, g: Field) -> sp.Expr:
        """``int_0^L rho_J f(x) g(x) dx``."""
        return contract(f, g, lambda a, b: self.section(axis, a, b))

    def section_integrate1(self, axis: str, f: Field) -> sp.Expr:
        """``int_0^L rho_J f(x) dx``."""
        from .modal_field import ONE

        return contract(Field({ONE: 1}), f, lambda a, b: self.section(axis, a, b))

    def model_values(self, beam, fields, parameters, stations: dict | None = None,
                     profiles: dict | None = None, model=None) -> dict:
        """Numeric value of every constant used (:meth:`SpatialBeamConstants.model_values`): the
        integrals of the shape functions read from the beam's invariants
        (:func:`flexkane.kane.modal_body.spatial_invariants`, each array computed once per parameter
        set), the values at stations and the loads' integrals as there."""
        from .modal_body import constant_value, spatial_invariants

        invariants = spatial_invariants(beam, fields, parameters, model)
        out, rest = {}, {}
        for symbol, spec in self.used.items():
            value = constant_value(invariants, spec)
            if value is None:
                rest[symbol] = spec
            else:
                out[symbol] = value
        used = self.used
        try:
            self.used = rest
            out.update(super().model_values(beam, fields, parameters, stations, profiles, model=model))
        finally:
            self.used = used
        return {symbol: out[symbol] for symbol in used}

