"""User-given shape functions: SymPy expressions of ``xi = x / L``.

Derivatives are taken symbolically (``sympy.diff``) and every derivative is compiled once with
``sympy.lambdify`` to NumPy. The expressions must depend on the symbol named ``xi`` only; build
them with ``sympy.Symbol("xi")`` or parse text with :func:`flexkane.expressions.parse_expression`.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import ModelError
from .base import END_CONDITIONS, ShapeFamily, as_abscissae, parse_boundary

if TYPE_CHECKING:
    import sympy

__all__ = ["Expression", "XI"]

#: The symbol of the dimensionless abscissa ``x / L``.
#: (SymPy is imported when the family is first used: loading :mod:`flexkane.modes` needs no SymPy.)


def __getattr__(name: str):
    if name == "XI":
        return _xi()
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def _xi():
    import sympy

    return sympy.Symbol("xi")   # SymPy caches symbols: every call gives the same object


def _as_expression(value: Any, k: int) -> "sympy.Expr":
    import sympy

    path = f"expressions[{k}]"
    if isinstance(value, str):
        raise ModelError(path, "a SymPy expression in xi", value,
                         hint="parse text with flexkane.expressions.parse_expression first")
    try:
        expr = sympy.sympify(value, strict=True)
    except (sympy.SympifyError, TypeError):
        raise ModelError(path, "a SymPy expression in xi", value) from None
    if not isinstance(expr, sympy.Expr):
        raise ModelError(path, "a SymPy expression in xi", value)
    others = sorted(str(s) for s in expr.free_symbols if s.name != "xi")
    if others:
        raise ModelError(path, "an expression of xi = x/L only", str(expr),
                         hint=f"unknown symbol(s) {', '.join(others)}")
    # adopt the package's xi, whatever assumptions the caller's symbol carries
    return expr.xreplace({s: _xi() for s in expr.free_symbols})


def _is_zero(value: "sympy.Expr") -> bool:
    """Whether a number found by substitution is zero (exactly, or to 1e-14 if a float)."""
    if value == 0:
        return True
    if value.is_number and value.is_finite:
        return abs(complex(value)) < 1e-14
    return False


class Expression(ShapeFamily):
    """Shape functions given as expressions of ``xi``.

    Parameters
    ----------
    expressions : list of sympy.Expr
        ``Phi_1 .. Phi_N`` in the symbol ``xi = sympy.Symbol("xi")``; ``n`` may not exceed ``N``.
    boundary : str, optional
        ``"<root>-<tip>"`` (e.g. ``"clamped-free"``) the functions must be admissible for; when
        given, :meth:`admissibility` is checked at once. Without it, ``boundary`` is
        ``"unspecified"``.
    """

    name = "expression"
    option_names = ("expressions", "boundary")

    def __init__(self, expressions: Any = None, boundary: str | None = None):
        import sympy

        XI = _xi()
        if expressions is None or isinstance(expressions, (str, sympy.Basic)) \
                or not hasattr(expressions, "__len__") or len(expressions) == 0:
            raise ModelError("expressions", "a non-empty list of SymPy expressions in xi",
                             expressions)
        exprs = tuple(_as_expression(e, k) for k, e in enumerate(expressions))
        super().__init__({"expressions": exprs} | ({} if boundary is None else {"boundary": boundary}))
        self.expressions = exprs
        self.boundary = "unspecified" if boundary is None else boundary
        self._derivatives = [[sympy.diff(e, XI, k) for k in range(5)] for e in exprs]
        self._functions = [[sympy.lambdify(XI, d, modules="numpy") for d in row]
                           for row in self._derivatives]
        probe = np.linspace(0.0, 1.0, 33)
        for k, row in enumerate(self._functions):
            with np.errstate(all="ignore"):
                values = self._call(row[0], probe)
            if not np.all(np.isfinite(values)):
                raise ModelError(f"expressions[{k}]",
                                 "a function finite on 0 <= xi <= 1", str(exprs[k]))
        if boundary is not None:
            self.admissibility(boundary)

    @property
    def max_modes(self) -> int:
        return len(self.expressions)

    @staticmethod
    def _call(function: Any, x: np.ndarray) -> np.ndarray:
        return np.broadcast_to(np.asarray(function(x), dtype=float), x.shape)

    def phi(self, xi: Any, n: int, deriv: int = 0) -> np.ndarray:
        """``d^k Phi_i / d xi^k`` of the first ``n`` expressions; shape ``(n, len(xi))``."""
        x = as_abscissae(xi)
        deriv = self._check_deriv(deriv)
        n = self._check_n(n)
        return np.vstack([self._call(row[deriv], x) for row in self._functions[:n]])

    def admissibility(self, boundary: str) -> None:
        """Check the geometric conditions of ``boundary`` exactly, by substitution.

        A clamped root requires ``Phi(0) = Phi'(0) = 0``, a pinned (or fixed) root ``Phi(0) = 0``;
        the tip end of ``"<root>-<tip>"`` likewise at ``xi = 1``.

        Raises
        ------
        ModelError
            Naming the expression, the condition and the value found.
        """
        import sympy

        XI = _xi()
        root, tip = parse_boundary(boundary)
        for end, point in ((root, 0), (tip, 1)):
            for order in END_CONDITIONS[end]:
                for k, row in enumerate(self._derivatives):
                    value = sympy.simplify(row[order].subs(XI, point))
                    if not _is_zero(value):
                        prime = "'" * order
                        raise ModelError(
                            f"expressions[{k}]",
                            f"Phi{prime}({point}) = 0 for a {end} end ({boundary})",
                            str(self.expressions[k]),
                            hint=f"Phi{prime}({point}) = {value}")
