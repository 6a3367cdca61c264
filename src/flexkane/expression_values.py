"""The value of a field of a model: in floating point from its syntax tree when it is simple, else through
the SymPy conversion.

:func:`field_value` builds on both modules of the expression language: it asks
:func:`flexkane.expression_syntax.simple_value` first, which needs no SymPy, and converts the expression
with :func:`flexkane.expressions.parse_expression` (imported only then) when that cannot answer, so that
validating a model whose fields are simple imports no SymPy.
"""

from __future__ import annotations

from collections.abc import Mapping

from .errors import ModelError
from .expression_syntax import NeedsSymbolic, simple_value

__all__ = ["field_value"]


def field_value(text, values: Mapping[str, float], *, path: str, what: str | None = None) -> float:
    """The value of a field: :func:`simple_value`, else through the SymPy conversion (same errors).

    Parameters
    ----------
    text : int, float or str
        A number or the text of an expression.
    values : Mapping[str, float]
        Values of the names it may use.
    path : str
        Key path of the field, for error messages.
    what : str, optional
        What the field is, with its unit (``"length [m]"``): an error then says that a field of this
        kind was expected (written in the language, with a finite real value at the given ``t``).

    Raises
    ------
    ModelError
        As :func:`flexkane.expressions.parse_expression` and :func:`flexkane.expressions.to_float` do.
    """
    try:
        return simple_value(text, values)
    except NeedsSymbolic:
        pass
    import sympy

    from .expressions import parse_expression, to_float

    symbols = {name: sympy.Symbol(name, real=True) for name in values}
    try:
        expr = parse_expression(text, symbols, path=path)
    except ModelError as exc:
        if what is None:
            raise
        raise ModelError(exc.path, f"{what}, written as {exc.expected}", exc.given, exc.hint) from None
    try:
        return to_float(expr, {symbols[name]: float(value) for name, value in values.items()}, path=path)
    except ModelError as exc:
        if what is None:
            raise
        where = f" at t = {float(values['t']):g}" if "t" in symbols and expr.has(symbols["t"]) else ""
        raise ModelError(path, f"{what} with a finite real value{where}", text, exc.hint) from None
