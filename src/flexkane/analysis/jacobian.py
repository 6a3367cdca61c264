"""Jacobians of large expressions by forward differentiation of their common subexpressions.

``sympy.Matrix.jacobian`` differentiates every entry with respect to every variable separately,
walking the whole expression each time; for the forcing of a beam with geometric stiffening and
eight modes that takes minutes. Here the expressions are first reduced to a sequence of common
subexpressions ``x_k = e_k(variables, x_1 .. x_{k-1})`` (``sympy.cse``); the gradient of each
``x_k`` then follows from the gradients of the earlier ones by the chain rule (forward-mode
automatic differentiation on the expression graph), every node being differentiated once:

    d x_k / d v_j = sum_s (partial e_k / partial s) (d s / d v_j),   s in the symbols of e_k.

The result is exact (symbolic) but kept in that factored form: a list of assignments and the
Jacobian entries in terms of them, ready for ``sympy.lambdify(..., cse=...)``.
"""

from __future__ import annotations

import keyword
from collections.abc import Sequence

import sympy as sp

__all__ = ["ForwardJacobian", "forward_jacobian", "numeric_function"]


class ForwardJacobian:
    """Values and Jacobian of a list of expressions, as assignments and final expressions.

    Attributes
    ----------
    assignments : list of (sympy.Symbol, sympy.Expr)
        In evaluation order; each expression uses the variables, the other free symbols of the
        input and the symbols assigned before it.
    values : list of sympy.Expr
        The input expressions in terms of the assignments, length m.
    jacobian : list of list of sympy.Expr
        ``d values[i] / d variables[j]``, shape (m, len(variables)).
    """

    def __init__(self, assignments, values, jacobian):
        self.assignments = assignments
        self.values = values
        self.jacobian = jacobian

    def cse(self, exprs):
        """The ``cse`` callable of ``sympy.lambdify``: these assignments, ``exprs`` unchanged."""
        return list(self.assignments), exprs


def forward_jacobian(exprs: Sequence[sp.Expr], variables: Sequence[sp.Symbol],
                     prefix: str = "_fj") -> ForwardJacobian:
    """Values and Jacobian of ``exprs`` with respect to ``variables`` (module docstring).

    Parameters
    ----------
    exprs : sequence of sympy.Expr
        m expressions.
    variables : sequence of sympy.Symbol
        The variables v_j.
    prefix : str
        Prefix of the names of the assigned symbols (must not be the name of any free symbol).

    Returns
    -------
    ForwardJacobian
    """
    replacements, reduced = sp.cse(list(exprs), symbols=sp.numbered_symbols(prefix, real=True), order="none",
                                   optimizations=None)
    index = {v: j for j, v in enumerate(variables)}
    gradients: dict = {}        # assigned symbol -> {j: derivative (an atom)}
    memo: dict = {}             # node -> {j: derivative}
    names = sp.numbered_symbols(prefix + "d")
    one = sp.Integer(1)

    def gradient(e) -> dict:
        if e in index:
            return {index[e]: one}
        if e in gradients:
            return gradients[e]
        if e.is_Atom:
            return {}
        if e in memo:
            return memo[e]
        terms: dict = {}

        def add(j, term):
            terms.setdefault(j, []).append(term)

        args = e.args
        if e.is_Add:
            for a in args:
                for j, d in gradient(a).items():
                    add(j, d)
        elif e.is_Mul:
            for k, a in enumerate(args):
                g = gradient(a)
                if g:
                    rest = sp.Mul(*(args[:k] + args[k + 1:]))
                    for j, d in g.items():
                        add(j, rest * d)
        elif e.is_Pow:
            base, exponent = args
            g_base, g_exp = gradient(base), gradient(exponent)
            if g_base:
                factor = exponent * base ** (exponent - 1)
                for j, d in g_base.items():
                    add(j, factor * d)
            if g_exp:
                for j, d in g_exp.items():
                    add(j, e * sp.log(base) * d)
        else:  # functions (sin, cos, Piecewise, ...): chain rule through their free symbols
            for symbol in e.free_symbols:
                g = gradient(symbol)
                if g:
                    partial = e.diff(symbol)
                    for j, d in g.items():
                        add(j, partial * d)
        result = {}
        for j, parts in terms.items():
            total = sp.Add(*parts)
            if total != 0:
                result[j] = total
        memo[e] = result
        return result

    assignments = []
    for symbol, expr in replacements:
        assignments.append((symbol, expr))
        named = {}
        for j, d in gradient(expr).items():
            if d.is_Atom:
                named[j] = d
            else:
                new = next(names)
                assignments.append((new, d))
                named[j] = new
        gradients[symbol] = named
    jacobian = [[sp.Integer(0)] * len(variables) for _ in reduced]
    for i, expr in enumerate(reduced):
        for j, d in gradient(expr).items():
            jacobian[i][j] = d
    return ForwardJacobian(assignments, list(reduced), jacobian)


def _renamed(exprs, names: dict):
    """``exprs`` (an expression, a matrix or nested lists and tuples of them) with ``names`` replaced."""
    if isinstance(exprs, (list, tuple)):
        return type(exprs)(_renamed(e, names) for e in exprs)
    return exprs.xreplace(names) if hasattr(exprs, "xreplace") else exprs


def numeric_function(args: Sequence[sp.Symbol], exprs, jacobian: ForwardJacobian | None = None):
    """``sympy.lambdify(args, exprs, modules="numpy")``, common subexpressions shared.

    lambdify replaces an argument whose name is not a Python identifier (a modal constant
    ``Phi_upper_y1(L1)``) by a dummy, walking the whole expression once per such argument, and walks
    it again for implemented functions: with the 18 of a spatial arm's two beams that was a quarter
    of its linearization. Here the common subexpressions are found first (``sympy.cse``, as
    lambdify's ``cse=True``), and the arguments renamed in them together, in one walk of the
    reduced expressions (``_arg0``, ``_arg1``, ...; the function is the same).

    Parameters
    ----------
    args : sequence of sympy.Symbol
        The arguments, in order.
    exprs : sympy.Expr, sympy.Matrix or nested lists of them
        What the function returns; with ``jacobian``, in terms of its assignments.
    jacobian : ForwardJacobian, optional
        Its assignments are the common subexpressions; without it ``sympy.cse`` finds them.

    Returns
    -------
    callable
    """
    if jacobian is None:     # as lambdify(cse=True) finds them
        assignments, exprs = sp.cse(exprs, list=False)
    else:
        assignments = list(jacobian.assignments)
    taken = {str(a) for a in args}
    names, k = {}, 0
    for a in args:
        if not (str(a).isidentifier() and not keyword.iskeyword(str(a))):
            while f"_arg{k}" in taken:
                k += 1
            names[a] = sp.Symbol(f"_arg{k}", **a.assumptions0)
            taken.add(f"_arg{k}")
    if names:
        args = [names.get(a, a) for a in args]
        exprs = _renamed(exprs, names)
        assignments = [(s, e.xreplace(names)) for s, e in assignments]
    from sympy.printing.numpy import NumPyPrinter

    # the printer lambdify makes for NumPy, but for the order of terms: as SymPy keeps them (its canonical
    # order, the same on every run), not sorted again for reading, which took half of the printing
    printer = NumPyPrinter({"fully_qualified_modules": False, "inline": True, "allow_unknown_functions": True,
                            "user_functions": {}, "order": "none"})
    return sp.lambdify(args, exprs, modules="numpy", printer=printer,
                       cse=ForwardJacobian(assignments, None, None).cse)
