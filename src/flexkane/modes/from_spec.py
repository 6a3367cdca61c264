"""The shape family of a beam's shape specification (a model file's ``shape`` or ``axial_shape``).

Needs no SymPy, except for the family ``expression`` whose functions are SymPy expressions of xi.
"""

from __future__ import annotations

from ..errors import ModelError
from ..expression_values import field_value
from . import get_family, numeric_option_names

__all__ = ["shape_family"]


def shape_family(spec, path: str, parameters=None):
    """The :class:`~flexkane.modes.ShapeFamily` of a beam's shape specification.

    Numeric options (typed ``roots``, the family's :attr:`~flexkane.modes.ShapeFamily.numeric_options`
    such as ``mass_ratio``) are numbers or expressions of the model's parameters, evaluated here
    with ``parameters``; they give numbers only, never structure, so one derivation serves every
    value (a sweep over a tip mass updates the modes through the modal constants). Expressions of
    ``xi`` given in a model file (family ``expression``) are parsed with the safe expression
    language and may use parameters too. Errors name the key path.

    Parameters
    ----------
    spec : ShapeSpec
        The beam's ``shape`` or ``axial_shape``.
    path : str
        Its key path (``beams.B.shape``).
    parameters : dict of str to float, optional
        Values of the model's parameters by name; without them only literal numbers are accepted.
    """
    parameters = {name: float(value) for name, value in (parameters or {}).items()}

    def number(value, where):
        if isinstance(value, bool) or not isinstance(value, (int, float, str)):
            return value   # the family reports what it expected
        if not isinstance(value, str):
            return value
        return field_value(value, parameters, path=where)

    options = dict(spec.options)
    if spec.roots is not None:
        roots = spec.roots
        options["roots"] = ([number(r, f"{path}.roots[{i}]") for i, r in enumerate(roots)]
                            if isinstance(roots, (list, tuple)) else roots)
    for option in numeric_option_names(spec.family):
        if option in options and option != "roots":
            options[option] = number(options[option], f"{path}.{option}")
    if spec.family == "expression" and "expressions" in options:
        texts = options["expressions"]
        if not isinstance(texts, list) or not texts:
            raise ModelError(f"{path}.expressions", "a non-empty list of expressions of xi", texts)
        import sympy as sp

        from ..expressions import parse_expression

        from . import XI

        symbols = {name: sp.Symbol(name, real=True) for name in parameters}
        numbers = {symbols[name]: value for name, value in parameters.items()}
        exprs = []
        for i, text in enumerate(texts):
            where = f"{path}.expressions[{i}]"
            expr = parse_expression(text, {**symbols, "xi": XI}, path=where)
            exprs.append(expr.xreplace({s: sp.Float(numbers[s]) for s in expr.free_symbols if s in numbers}))
        options["expressions"] = exprs
    try:
        return get_family(spec.family, **options)
    except ModelError as exc:
        raise ModelError(f"{path}.{exc.path}" if exc.path != "family" else f"{path}.family",
                         exc.expected, exc.given, exc.hint) from None
