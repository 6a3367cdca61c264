"""Named intermediate quantities: kinematics that never re-expand along a chain.

The velocity of a link's frame is built from its parent's (eq. 8.17: ``v_C = R(-phi)(v_A + w_A x d
+ d')``). Written out in full, the expressions of link k contain those of every earlier link, so
their size grows geometrically with the length of the chain, and every partial velocity (eq. 8.20)
and acceleration (eq. 8.21) re-expands them. Here a quantity whose expression exceeds
:data:`NAME_ABOVE` operations is replaced by a symbol of its own, an :class:`Intermediate`, whose
definition is kept; later links refer to the symbol. The size of every definition is then bounded
by a constant, whatever the position of the link in the chain.

The calculus of Kane's method goes through the definitions by the chain rule, each derivative of an
intermediate being itself an intermediate (or an inline expression when it is small), created once:

* partial derivative with respect to a speed u_r (the partial velocities of eq. 8.20):
  ``d s / d u_r = d e_s / d u_r + sum_j (d e_s / d s_j)(d s_j / d u_r)``;
* time derivative without the terms in u' (the acceleration remainder of eq. 8.21):
  ``ds/dt = sum_q (d e_s / d q) q' + sum_j (d e_s / d s_j)(d s_j / dt) + d e_s / d t``.

Definitions are recorded in the order of creation, which is an evaluation order (each refers only to
earlier ones): the tree order of the chain, from the ground outwards. Generated code evaluates them
in that order, so one evaluation of the right-hand side costs in proportion to the number of links.
"""

from __future__ import annotations

import sympy as sp

from ..model.values import GeneratedSymbol

__all__ = ["FRAME_NAME_ABOVE", "Intermediate", "Intermediates", "NAME_ABOVE", "needed_definitions",
           "written_out"]

#: An expression with more operations than this (``sympy.count_ops``) is named. Small enough that the
#: size of every definition stays bounded; large enough that a chain of one link (the chapter's
#: example) has no intermediates at all, so its equations print as eqs. 8.23 and 8.31.
NAME_ABOVE = 24
#: The same for the quantities of a link's frame (angle, angular velocity, position and velocity of
#: its origin), which every later link refers to: named as soon as they are more than a few
#: operations (the sum of the joint angles before them, for instance).
FRAME_NAME_ABOVE = 4


class Intermediate(GeneratedSymbol):
    """A symbol standing for a kinematic quantity whose definition is kept by :class:`Intermediates`."""


def needed_definitions(definitions, exprs) -> list:
    """The definitions that ``exprs`` need, directly or through other definitions.

    Parameters
    ----------
    definitions : sequence of (Symbol, Expr)
        Definitions in evaluation order (each refers only to earlier ones).
    exprs : iterable of sympy.Expr

    Returns
    -------
    list of (Symbol, Expr)
        The needed ones, in evaluation order.
    """
    index = dict(definitions)
    if not index:
        return []
    needed: set = set()
    stack = [s for e in exprs for s in sp.sympify(e).free_symbols if s in index]
    while stack:
        s = stack.pop()
        if s not in needed:
            needed.add(s)
            stack += [x for x in index[s].free_symbols if x in index and x not in needed]
    return [(s, e) for s, e in index.items() if s in needed]


def written_out(definitions, fits=None, full: dict | None = None) -> dict | None:
    """Each symbol of ``definitions`` (evaluation order) mapped to its definition written out in full.

    ``fits(expr) -> bool``, when given, is asked of each written-out definition; the first that does
    not fit gives None. ``full``, when given, holds definitions written out already (those of the
    symbols ``definitions`` refer to and does not list); it is extended and returned.
    """
    full = {} if full is None else full
    for symbol, definition in definitions:    # earlier ones are written out already
        full[symbol] = definition.xreplace(full)
        if fits is not None and not fits(full[symbol]):
            return None
    return full


class Intermediates:
    """The ordered definitions of a chain's intermediate quantities, and calculus through them.

    Parameters
    ----------
    qdot : dict of Symbol to Expr
        Kinematic differential equations ``q' = ...`` of every coordinate (shared with the chain).
    t : sympy.Symbol
        Time [s].
    """

    def __init__(self, qdot: dict, t: sp.Symbol):
        self.qdot = qdot
        self.t = t
        #: symbol -> definition, in evaluation order
        self.definitions: dict[Intermediate, sp.Expr] = {}
        #: symbol -> coordinates, speeds and t its value depends on (through earlier intermediates too)
        self.depends: dict[Intermediate, frozenset] = {}
        self._partial: dict[tuple, sp.Expr] = {}
        self._rate: dict[Intermediate, sp.Expr] = {}
        self._names: set[str] = set()
        self._created: dict[Intermediate, int] = {}     # creation index of each intermediate
        self._written: dict[Intermediate, sp.Expr] = {}   # definitions written out so far

    # ------------------------------------------------------------------ naming
    def _unique(self, label: str) -> str:
        name, k = label, 1
        while name in self._names:
            k += 1
            name = f"{label}_{k}"
        self._names.add(name)
        return name

    def dependencies(self, expr: sp.Expr) -> frozenset:
        """Coordinates, speeds and t on which ``expr`` depends, through its intermediates too."""
        out = set()
        for s in expr.free_symbols:
            if s in self.depends:
                out |= self.depends[s]
            else:
                out.add(s)
        return frozenset(out)

    def name(self, expr, label: str, above: int = NAME_ABOVE) -> sp.Expr:
        """``expr`` itself when small or constant, else a new intermediate defined by it.

        Parameters
        ----------
        expr : sympy.Expr
        label : str
            Base of the symbol's name (made unique by a suffix ``_2``, ``_3`` ...).
        above : int
            Name ``expr`` when it has more operations than this.
        """
        expr = sp.sympify(expr)
        if expr.is_Atom or sp.count_ops(expr) <= above:
            return expr
        symbol = Intermediate(self._unique(label), real=True)
        self.definitions[symbol] = expr
        self._created[symbol] = len(self._created)
        self.depends[symbol] = self.dependencies(expr)
        return symbol

    def _among(self, expr) -> list:
        """The intermediates ``expr`` refers to, in creation order: derivatives through them are then
        created (and named) in the same order whatever the order of a set of symbols, which depends
        on the process's string hashing."""
        found = [s for s in expr.free_symbols if s in self.definitions]
        return sorted(found, key=self._created.__getitem__) if len(found) > 1 else found

    # ------------------------------------------------------------------ calculus
    def partial(self, expr, u: sp.Symbol) -> sp.Expr:
        """Total partial derivative of ``expr`` with respect to the speed (or coordinate) ``u``."""
        expr = sp.sympify(expr)
        if expr.is_Number:      # a constant component (the zeros of a planar chain's vectors)
            return sp.S.Zero
        terms = [sp.diff(expr, u)]
        for s in self._among(expr):
            ds = self.partial_of(s, u)
            if ds != 0:
                terms.append(sp.diff(expr, s) * ds)
        return sp.Add(*terms)

    def partial_of(self, s: Intermediate, u: sp.Symbol) -> sp.Expr:
        """``d s / d u`` (named when large), created once."""
        if u not in self.depends[s]:
            return sp.Integer(0)
        key = (s, u)
        if key not in self._partial:
            self._partial[key] = self.name(self.partial(self.definitions[s], u), f"d{s.name}_d{u.name}")
        return self._partial[key]

    def rate(self, expr, speeds_rates: dict | None = None) -> sp.Expr:
        """Total time derivative of ``expr`` without its terms in u' (unless ``speeds_rates``).

        Parameters
        ----------
        expr : sympy.Expr
        speeds_rates : dict of Symbol to Symbol, optional
            Speed -> symbol of its derivative u'; when given, the terms in u' are included.
        """
        expr = sp.sympify(expr)
        if expr.is_Number:
            return sp.S.Zero
        free = expr.free_symbols
        terms = [sp.diff(expr, q) * qd for q, qd in self.qdot.items() if q in free]
        if speeds_rates:
            terms += [sp.diff(expr, u) * ud for u, ud in speeds_rates.items() if u in free]
        for s in self._among(expr):
            ds = self.rate_of(s)
            if speeds_rates:
                ds = ds + sp.Add(*[self.partial_of(s, u) * ud for u, ud in speeds_rates.items()])
            if ds != 0:
                terms.append(sp.diff(expr, s) * ds)
        if self.t in free:
            terms.append(sp.diff(expr, self.t))
        return sp.Add(*terms)

    def rate_of(self, s: Intermediate) -> sp.Expr:
        """``ds/dt`` without the terms in u' (named when large), created once."""
        if s not in self._rate:
            deps = self.depends[s]
            if not any(x in deps for x in self.qdot) and self.t not in deps:
                self._rate[s] = sp.Integer(0)      # a function of speeds only: all of it is in u'
            else:
                self._rate[s] = self.name(self.rate(self.definitions[s]), f"{s.name}_dot")
        return self._rate[s]

    # ------------------------------------------------------------------ evaluation
    def expand(self, expr, keep=frozenset()) -> sp.Expr:
        """``expr`` with every intermediate replaced by its definition, recursively; the symbols of
        ``keep`` stay as they are (a printed definition of a controller output names the outputs it
        uses instead of writing each out again: twenty chained outputs print in linear size)."""
        expr = sp.sympify(expr)
        if keep:
            used = needed_definitions([(s, d) for s, d in self.definitions.items() if s not in keep], [expr])
            return expr.xreplace(written_out(used)) if used else expr
        used = needed_definitions(self.definitions.items(), [expr])
        if not used:
            return expr
        written_out([(s, d) for s, d in used if s not in self._written], full=self._written)
        return expr.xreplace({s: self._written[s] for s, _ in used})

    def __getstate__(self):
        state = dict(self.__dict__)
        state["_written"] = {}      # a cache: not worth storing
        return state

    def used_by(self, exprs) -> list[tuple[Intermediate, sp.Expr]]:
        """The definitions that ``exprs`` need, in evaluation order, as (symbol, expression) pairs."""
        return needed_definitions(self.definitions.items(), exprs)
