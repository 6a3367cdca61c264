"""Kane's equations in compact form: named intermediates first, then the equations in their terms.

:class:`CompactEquations` holds what generated code evaluates, in order: the definitions of the
intermediate quantities of :mod:`flexkane.kane.intermediates` (tree order: ground outwards), then
``q' = qdot``, ``M u' = f`` and the outputs, all in terms of them. Prescribed coordinates (drivers)
and dependent speeds (closed loops) are substituted in the definitions as in the equations; the
substitution may make an early definition refer to a later one, so the order is re-established
(stable topological order).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import sympy as sp

from .intermediates import written_out

__all__ = ["CompactEquations", "LazyMassMatrix"]


class LazyMassMatrix:
    """The mass matrix of a chain whose generated code sums ``M`` from its
    :class:`flexkane.kane.inertia.MassAssembly`: each entry is formed when read, the same
    expression as the written-out matrix's, so that nothing pays for the entries nothing reads.

    Forming an entry may name new intermediates (partial derivatives of the kinematics); the
    compact equations it belongs to then take them into their definitions.

    Parameters
    ----------
    inertia : InertiaForces
        With :attr:`~flexkane.kane.inertia.InertiaForces.lazy` entries.
    rows : list of int
        The speeds of the chain (indices in ``inertia.speeds``) of the rows and columns.
    registry : Intermediates
        The chain's definitions.
    """

    lazy = True

    def __init__(self, inertia, rows: list, registry):
        self.inertia = inertia
        self.rows = list(rows)
        self.registry = registry
        self.shape = (len(self.rows), len(self.rows))
        self.owner = None      # the CompactEquations holding this matrix

    def __getitem__(self, key) -> sp.Expr:
        i, j = key
        known = len(self.registry.definitions)
        entry = self.inertia.entry(self.rows[i], self.rows[j])
        if len(self.registry.definitions) != known and self.owner is not None:
            self.owner.take_definitions(self.registry)
        return entry

    def formed(self) -> sp.Matrix:
        """Every entry, as a sympy Matrix."""
        n = self.shape[0]
        return sp.Matrix(n, n, lambda i, j: self[i, j])

    def xreplace(self, rule: dict) -> sp.Matrix:
        return self.formed().xreplace(rule)

    def __array__(self, dtype=None, copy=None):
        """Every entry, as an object array (what ``sympy.Matrix(self)`` reads)."""
        import numpy as np

        return np.array(self.formed().tolist(), dtype=object)


@dataclass
class CompactEquations:
    """Equations of motion in terms of named intermediates.

    Attributes
    ----------
    intermediates : list of (Intermediate, sympy.Expr)
        Definitions in evaluation order; each refers only to earlier ones, q, u, t and constants.
    mass_matrix : sympy.Matrix or LazyMassMatrix, shape (nu, nu)
    forcing : sympy.Matrix, shape (nu, 1)
    qdot : sympy.Matrix, shape (nq, 1)
    outputs : dict of str to sympy.Expr
    zdot : sympy.Matrix, shape (nz, 1)
        Rates of the controller states (:mod:`flexkane.kane.controllers`).
    mass_assembly : MassAssembly or None
        The same ``mass_matrix`` as twists and composite bodies in terms of the intermediates
        (:class:`flexkane.kane.inertia.MassAssembly`, rows numbered as ``u``), which generated code
        of a long chain sums by a compiled loop; None when not available (closed loops).
    """

    intermediates: list
    mass_matrix: sp.Matrix
    forcing: sp.Matrix
    qdot: sp.Matrix
    outputs: dict
    zdot: sp.Matrix = field(default_factory=lambda: sp.zeros(0, 1))
    mass_assembly: object = None

    @classmethod
    def collect(cls, eom, registry, sub, dependent: dict, mass_assembly=None) -> "CompactEquations":
        """The compact equations of ``eom`` (during its construction) from the chain's registry.

        Parameters
        ----------
        eom : EquationsOfMotion
            With ``mass_matrix``, ``forcing``, ``qdot``, ``outputs`` still in compact form.
        registry : Intermediates
            The chain's definitions.
        sub : callable
            Substitution of the drivers' laws.
        dependent : dict
            Dependent speed -> its expression in the independent ones (closed loops), or empty.
        mass_assembly : MassAssembly, optional
            ``mass_matrix`` as twists and composites, drivers substituted (kept only without
            dependent speeds, whose reduction mixes the rows).
        """
        M, f, qdot, outputs, zdot = eom.mass_matrix, eom.forcing, eom.qdot, dict(eom.outputs), eom.zdot
        # every definition is kept (generated code takes those it needs): other expressions of the
        # kinematics (the spin of a beam's frame for the validity checks) may use any of them
        definitions = {s: sub(d).xreplace(dependent) if dependent else sub(d)
                       for s, d in registry.definitions.items()}
        order = {s: k for k, s in enumerate(registry.definitions)}
        compact = cls(_topological(definitions, order), M, f, qdot, outputs, zdot,
                      None if dependent else mass_assembly)
        if isinstance(M, LazyMassMatrix):
            M.owner = compact
        return compact

    def take_definitions(self, registry) -> None:
        """Take the definitions ``registry`` gained since (those a :class:`LazyMassMatrix`'s entries
        named; its equations have no substitutions), in evaluation order."""
        order = {s: k for k, s in enumerate(registry.definitions)}
        self.intermediates = _topological(dict(registry.definitions), order)
        self._full_memo = None

    # ------------------------------------------------------------------ views
    def expressions(self) -> list:
        """Every expression: definitions, q', M (all entries; for a :class:`LazyMassMatrix`, its
        assembly's expressions), f, outputs."""
        mass = self.mass_assembly.expressions() if isinstance(self.mass_matrix, LazyMassMatrix) \
            else self.mass_matrix
        return [*(e for _, e in self.intermediates), *self.qdot, *mass, *self.forcing,
                *self.outputs.values(), *self.zdot]

    def expand(self, expr):
        """``expr`` with every intermediate replaced by its full definition."""
        if isinstance(expr, LazyMassMatrix):
            expr = expr.formed()
        if not self.intermediates:
            return expr
        full = self._full()
        if isinstance(expr, sp.MatrixBase):
            return expr.applyfunc(lambda e: e.xreplace(full))
        return sp.sympify(expr).xreplace(full)

    def _full(self) -> dict:
        if getattr(self, "_full_memo", None) is None:
            self._full_memo = written_out(self.intermediates)
        return self._full_memo

    def expanded(self) -> "CompactEquations":
        """The same equations without intermediates."""
        if not self.intermediates and not isinstance(self.mass_matrix, LazyMassMatrix):
            return self
        return CompactEquations([], self.expand(self.mass_matrix), self.expand(self.forcing),
                                self.expand(self.qdot), {k: self.expand(v) for k, v in self.outputs.items()},
                                self.expand(self.zdot))   # no assembly: its terms refer to intermediates

    def __getstate__(self):
        state = dict(self.__dict__)
        state.pop("_full_memo", None)
        return state


def _topological(definitions: dict, order: dict) -> list:
    """(symbol, definition) pairs, each after those it refers to, otherwise in creation order."""
    done: set = set()
    out = []
    for root in sorted(definitions, key=order.__getitem__):
        if root in done:
            continue
        stack = [(root, False)]
        while stack:
            s, expanded = stack.pop()
            if s in done:
                continue
            if expanded:
                done.add(s)
                out.append((s, definitions[s]))
                continue
            stack.append((s, True))
            deps = sorted((x for x in definitions[s].free_symbols if x in definitions and x not in done),
                          key=order.__getitem__, reverse=True)
            stack += [(x, False) for x in deps]
    return out
