"""Safe expression language of model files.

A model file may write any physical value as a short formula, e.g. ``"sin(2*pi*t/T)"`` or
``"mR*(c**2 + d**2)/12"``. Model files are untrusted, so the text is never handed to ``eval``,
``sympify`` or ``parse_expr``: :func:`parse_expression` parses it with :func:`ast.parse` and
converts a strict whitelist of syntax into SymPy objects built directly.

The language
------------
* numbers (``2``, ``0.5``, ``1e-3``), the constant ``pi`` and the names the caller allows;
* ``+ - * / **`` and unary ``+ -``;
* ``sin cos tan exp log sqrt sinh cosh tanh abs`` (one argument), ``min max`` (two or more);
* ``where(cond, a, b)``: ``a`` where ``cond`` holds, else ``b``;
* ``piecewise(a1, cond1, a2, cond2, ..., default)``: the first ``a_k`` whose ``cond_k`` holds,
  else ``default`` (an odd number of arguments, at least three);
* conditions, only as the condition arguments above: ``< <= > >=`` (chains such as
  ``0 < t < 1`` too) combined with ``and``, ``or``, ``not``.

Limits keep every parse fast whatever the input: at most :data:`MAX_LENGTH` characters,
:data:`MAX_NODES` syntax elements, :data:`MAX_DEPTH` levels of nesting, integer literals up to
:data:`MAX_INTEGER`, and numeric exponents up to :data:`MAX_EXPONENT` in absolute value. Every
constant part of an expression is also evaluated in floating point while it is built, so that
overflows, divisions by zero and roots of negative numbers are reported at their column, before
SymPy is asked to compute anything large.
"""

from __future__ import annotations

import ast
import difflib
import math
import numbers
import operator
from collections.abc import Mapping
from typing import NamedTuple

import sympy

from .errors import ModelError
from .expression_syntax import (_ADDITIVE, _BINARY, _EXPECTED, _MAX_COEFFICIENT_BITS, _MULTIPLICATIVE, FUNCTIONS,
                                MAX_DEPTH, MAX_EXPONENT, MAX_INTEGER, MAX_LENGTH, MAX_NODES, RESERVED_NAMES, _check_size,
                                _shorten, _Source, _syntax_tree, check_parameter_name, dependency_order)

__all__ = ["FUNCTIONS", "MAX_DEPTH", "MAX_EXPANDED_TERMS", "MAX_EXPONENT", "MAX_INTEGER", "MAX_LENGTH",
           "MAX_NODES", "bounded_expand", "expansion_terms", "time_derivative",
           "RESERVED_NAMES", "free_names", "parse_condition", "parse_expression",
           "resolve_parameters", "to_float"]

#: One-argument functions: name -> (SymPy function, float function).
_UNARY = {
    "sin": (sympy.sin, math.sin), "cos": (sympy.cos, math.cos), "tan": (sympy.tan, math.tan),
    "exp": (sympy.exp, math.exp), "log": (sympy.log, math.log), "sqrt": (sympy.sqrt, math.sqrt),
    "sinh": (sympy.sinh, math.sinh), "cosh": (sympy.cosh, math.cosh),
    "tanh": (sympy.tanh, math.tanh), "abs": (sympy.Abs, abs),
}
_VARIADIC = {"min": (sympy.Min, min), "max": (sympy.Max, max)}
_CONSTANTS = {"pi": (sympy.pi, math.pi)}

assert FUNCTIONS == tuple(sorted([*_UNARY, *_VARIADIC, "where", "piecewise"]))
assert RESERVED_NAMES == frozenset([*FUNCTIONS, *_CONSTANTS])
_COMPARISONS = {ast.Lt: ("<", sympy.Lt, operator.lt), ast.LtE: ("<=", sympy.Le, operator.le),
                ast.Gt: (">", sympy.Gt, operator.gt), ast.GtE: (">=", sympy.Ge, operator.ge)}
_REFUSED_COMPARISONS = {ast.Eq: "==", ast.NotEq: "!=", ast.Is: "is", ast.IsNot: "is not",
                        ast.In: "in", ast.NotIn: "not in"}


def _describe_node(node: ast.AST) -> str:
    """Name a refused piece of syntax the way a user would."""
    names = {
        ast.Subscript: "subscript '[...]'", ast.Lambda: "lambda", ast.ListComp:
        "list comprehension", ast.SetComp: "set comprehension", ast.DictComp:
        "dict comprehension", ast.GeneratorExp: "generator expression", ast.Dict: "dict literal",
        ast.Set: "set literal", ast.List: "list literal", ast.Tuple: "tuple",
        ast.JoinedStr: "f-string", ast.NamedExpr: "assignment expression ':='",
        ast.IfExp: "conditional expression 'if ... else'", ast.Starred: "starred argument '*'",
        ast.Await: "'await'", ast.Yield: "'yield'", ast.YieldFrom: "'yield from'",
        ast.Slice: "slice",
    }
    if isinstance(node, ast.Attribute):
        return f"attribute access '.{node.attr}'"
    if isinstance(node, ast.Constant):
        kind = {str: "string literal", bytes: "bytes literal", complex: "complex number"}
        return f"{kind.get(type(node.value), 'constant')} {_shorten(repr(node.value), 30)}"
    return names.get(type(node), f"'{type(node).__name__}' syntax")


def _as_float(number: sympy.Expr) -> float:
    """Float value of a SymPy number, infinite when out of range."""
    try:
        return float(number)
    except OverflowError:
        return math.inf


def _magnitude_bits(number: sympy.Expr) -> int:
    """Number of bits of the larger of numerator and denominator (binary exponent of a Float)."""
    if isinstance(number, sympy.Rational):
        return max(int(number.p).bit_length(), int(number.q).bit_length())
    if isinstance(number, sympy.Float):
        _, mantissa, exponent, bits = number._mpf_
        return abs(exponent + bits) if mantissa else 0
    return 0


def _bound(expr: sympy.Expr) -> float | None:
    """Largest absolute value a piecewise, min or max of numbers can take (else None)."""
    if expr.is_Number:
        return abs(_as_float(expr))
    if isinstance(expr, (sympy.Piecewise, sympy.Min, sympy.Max)):
        pieces = [arg.args[0] if isinstance(expr, sympy.Piecewise) else arg for arg in expr.args]
        bounds = [_bound(piece) for piece in pieces]
        return None if None in bounds else max(bounds)
    return None


class _Value(NamedTuple):
    """A converted value: its SymPy expression, and its float value when it is a constant."""

    expr: sympy.Expr
    estimate: float | None


class _Condition(NamedTuple):
    expr: sympy.Basic
    estimate: bool | None


class _Converter:
    """Convert a checked syntax tree into SymPy objects (see the module docstring)."""

    def __init__(self, text: str, source: _Source, names: Mapping[str, sympy.Expr], path: str):
        self.text, self.source, self.names, self.path = text, source, names, path

    # -- errors -------------------------------------------------------------------------
    def refuse(self, at: ast.AST | int, what: str, hint: str | None = None):
        """Raise a ModelError for ``what``, found at a node or character index."""
        index = at if isinstance(at, int) else self.source.start(at)
        message = f"{what} at {self.source.where(index)}"
        raise ModelError(self.path, _EXPECTED, _shorten(self.text),
                         f"{message}; {hint}" if hint else message)

    def refuse_syntax(self, node: ast.AST):
        if isinstance(node, ast.Attribute):
            attribute = self.source.find("." + node.attr, self.source.end(node.value),
                                         self.source.end(node))
            self.refuse(attribute, _describe_node(node) + " is not allowed")
        if isinstance(node, ast.IfExp):
            self.refuse(node, _describe_node(node) + " is not allowed",
                        "write where(condition, a, b)")
        self.refuse(node, _describe_node(node) + " is not allowed")

    def checked(self, value: _Value, at: ast.AST | int) -> _Value:
        """Fill in the float value of a numeric result and refuse one out of range."""
        estimate = value.estimate
        if estimate is None and value.expr.is_Number:
            estimate = _as_float(value.expr)
        if estimate is not None and not math.isfinite(estimate):
            self.refuse(at, "a number beyond the floating-point range")
        if value.expr.is_Number and _magnitude_bits(value.expr) > _MAX_COEFFICIENT_BITS:
            self.refuse(at, "an exact number with too many digits")
        for factor in sympy.Mul.make_args(value.expr):   # powers of powers combine: (x**a)**b
            if factor.is_Pow and factor.exp.is_Number and abs(factor.exp) > MAX_EXPONENT:
                self.refuse(at, f"a power with the combined exponent {factor.exp} above "
                            f"{MAX_EXPONENT} in absolute value")
        return _Value(value.expr, estimate)

    def compute(self, function, *arguments, at: ast.AST | int, name: str) -> float | None:
        """Apply a float function to known constants, refusing overflow and domain errors."""
        if any(argument is None for argument in arguments):
            return None
        try:
            result = function(*arguments)
        except OverflowError:
            self.refuse(at, f"{name} overflows the floating-point range")
        except ZeroDivisionError:
            self.refuse(at, f"{name} divides by zero")
        except ValueError:
            self.refuse(at, f"{name} is not defined for these constant arguments")
        if isinstance(result, complex):
            self.refuse(at, f"{name} is not a real number")
        return float(result)

    # -- values -------------------------------------------------------------------------
    def value(self, node: ast.AST) -> _Value:
        """Convert an expression that stands for a number."""
        if isinstance(node, ast.BinOp) and type(node.op) in _BINARY:
            if isinstance(node.op, _ADDITIVE + _MULTIPLICATIVE):
                return self.chain(node)
            if isinstance(node.op, ast.Pow):
                return self.power(node)
            symbol = _BINARY[type(node.op)]
            at = self.source.find(symbol, self.source.end(node.left), self.source.start(node.right))
            self.refuse(at, f"operator '{symbol}' is not allowed",
                        "write ** for a power" if symbol == "^" else None)
        if isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.USub, ast.UAdd)):
            operand = self.value(node.operand)
            if isinstance(node.op, ast.UAdd):
                return operand
            estimate = None if operand.estimate is None else -operand.estimate
            return self.checked(_Value(sympy.Mul(sympy.S.NegativeOne, operand.expr), estimate),
                                node)
        if isinstance(node, ast.Constant):
            return self.constant(node)
        if isinstance(node, ast.Name):
            return self.name(node)
        if isinstance(node, ast.Call):
            return self.call(node)
        if isinstance(node, (ast.Compare, ast.BoolOp)) or (
                isinstance(node, ast.UnaryOp) and isinstance(node.op, ast.Not)):
            self.refuse(node, f"condition '{self.source.segment(node)}' where a value is expected",
                        "comparisons, and, or, not are allowed only in the conditions of "
                        "where() and piecewise()")
        if isinstance(node, ast.UnaryOp):
            self.refuse(node, "operator '~' is not allowed")
        self.refuse_syntax(node)

    def constant(self, node: ast.Constant) -> _Value:
        number = node.value
        if isinstance(number, bool) or not isinstance(number, (int, float)):
            self.refuse_syntax(node)
        if isinstance(number, int):
            if abs(number) > MAX_INTEGER:
                self.refuse(node, f"integer {self.source.segment(node)} above {MAX_INTEGER:.0e}",
                            "write large numbers in floating point, e.g. 1e20")
            return _Value(sympy.Integer(number), float(number))
        if not math.isfinite(number):
            self.refuse(node, f"number {self.source.segment(node)} beyond the floating-point range")
        return _Value(sympy.Float(number), number)

    def name(self, node: ast.Name) -> _Value:
        if node.id in self.names:
            return self.checked(_Value(self.names[node.id], None), node)
        if node.id in _CONSTANTS:
            return _Value(*_CONSTANTS[node.id])
        if node.id in FUNCTIONS:
            self.refuse(node, f"function '{node.id}' without arguments",
                        f"write {node.id}(...)")
        known = [*self.names, *_CONSTANTS]
        self.refuse(node, f"unknown name '{node.id}'", _suggest(node.id, known, "allowed names"))

    def chain(self, node: ast.BinOp) -> _Value:
        """Convert ``a + b - c ...`` or ``a * b / c ...`` as one sum or product."""
        kinds = _ADDITIVE if isinstance(node.op, _ADDITIVE) else _MULTIPLICATIVE
        links = []
        while isinstance(node, ast.BinOp) and isinstance(node.op, kinds):
            links.append(node)
            node = node.left
        first = self.value(node)
        parts, estimate = [first.expr], first.estimate
        for link in reversed(links):
            right = self.value(link.right)
            symbol = _BINARY[type(link.op)]
            at = self.source.find(symbol, self.source.end(link.left), self.source.start(link.right))
            if isinstance(link.op, ast.Sub):
                parts.append(sympy.Mul(sympy.S.NegativeOne, right.expr))
                estimate = self.compute(operator.sub, estimate, right.estimate, at=at, name="'-'")
            elif isinstance(link.op, ast.Add):
                parts.append(right.expr)
                estimate = self.compute(operator.add, estimate, right.estimate, at=at, name="'+'")
            elif isinstance(link.op, ast.Mult):
                parts.append(right.expr)
                estimate = self.compute(operator.mul, estimate, right.estimate, at=at, name="'*'")
            else:
                if right.expr.is_zero or right.estimate == 0:
                    self.refuse(at, "division by zero (or by a number too close to zero)")
                parts.append(sympy.Pow(right.expr, sympy.S.NegativeOne))
                estimate = self.compute(operator.truediv, estimate, right.estimate, at=at,
                                        name="'/'")
            if estimate is not None and not math.isfinite(estimate):
                self.refuse(at, "a number beyond the floating-point range")
        combine = sympy.Add if kinds is _ADDITIVE else sympy.Mul
        return self.checked(_Value(combine(*parts), estimate), links[0])

    def power(self, node: ast.BinOp) -> _Value:
        base, exponent = self.value(node.left), self.value(node.right)
        at = self.source.find("**", self.source.end(node.left), self.source.start(node.right))
        bound = exponent.estimate if exponent.estimate is not None else _bound(exponent.expr)
        if bound is not None:
            if abs(bound) > MAX_EXPONENT:
                self.refuse(node.right, f"exponent {self.source.segment(node.right)} above "
                            f"{MAX_EXPONENT} in absolute value")
            coefficient = base.expr.as_coeff_Mul()[0]
            if _magnitude_bits(coefficient) * abs(bound) > _MAX_COEFFICIENT_BITS:
                self.refuse(at, "a power of a number with too many digits")
        estimate = self.compute(operator.pow, base.estimate, exponent.estimate, at=at,
                                name="'**'")
        return self.checked(_Value(sympy.Pow(base.expr, exponent.expr), estimate), node)

    def call(self, node: ast.Call) -> _Value:
        if not isinstance(node.func, ast.Name):
            if isinstance(node.func, ast.Attribute):
                self.refuse_syntax(node.func)
            self.refuse(node, "call of an expression", "only the functions "
                        + " ".join(FUNCTIONS) + " can be called")
        name = node.func.id
        if name not in FUNCTIONS:
            if name in self.names or name in _CONSTANTS:
                self.refuse(node.func, f"call of '{name}', which is not a function",
                            f"write {name}*(...) for a product")
            self.refuse(node.func, f"unknown function '{name}'",
                        _suggest(name, FUNCTIONS, "allowed functions"))
        for argument in node.keywords:
            what = (f"keyword argument '{argument.arg}='" if argument.arg
                    else "keyword argument unpacking '**'")
            self.refuse(argument, what + " is not allowed")
        for argument in node.args:
            if isinstance(argument, ast.Starred):
                self.refuse_syntax(argument)
        count = len(node.args)
        if name in _UNARY and count != 1:
            self.refuse(node.func, f"{name}() with {count} arguments", "it takes 1 argument")
        if name in _VARIADIC and count < 2:
            self.refuse(node.func, f"{name}() with {count} argument(s)", "it takes 2 or more")
        if name == "where" and count != 3:
            self.refuse(node.func, f"where() with {count} arguments",
                        "write where(condition, value_if_true, value_otherwise)")
        if name == "piecewise" and (count < 3 or count % 2 == 0):
            self.refuse(node.func, f"piecewise() with {count} arguments",
                        "write piecewise(a1, condition1, a2, condition2, ..., default)")
        if name in ("where", "piecewise"):
            return self.checked(self.branches(node.args, swap=name == "where"), node)
        values = [self.value(argument) for argument in node.args]
        exprs = [value.expr for value in values]
        estimates = [value.estimate for value in values]
        if name in _VARIADIC:
            build, compute = _VARIADIC[name]
            if None in estimates:  # SymPy compares symbolic arguments pairwise: keep them as given
                return _Value(build(*exprs, evaluate=False), None)
            return self.checked(_Value(build(*exprs), compute(estimates)), node)
        build, compute = _UNARY[name]
        estimate = self.compute(compute, *estimates, at=node, name=f"{name}()")
        if name == "exp":
            self.check_exp_argument(exprs[0], node)
        return self.checked(_Value(build(exprs[0]), estimate), node)

    def check_exp_argument(self, argument: sympy.Expr, node: ast.AST):
        """Refuse ``exp(c*log(x))`` with a large ``c``: SymPy rewrites it as ``x**c``."""
        if not argument.has(sympy.log):
            return
        for term in sympy.Add.make_args(argument):
            if term.has(sympy.log) and abs(_as_float(term.as_coeff_Mul()[0])) > MAX_EXPONENT:
                self.refuse(node, f"exp() of a logarithm times a number above {MAX_EXPONENT}",
                            "it is a power with too large an exponent")

    def branches(self, arguments: list[ast.expr], swap: bool) -> _Value:
        """Build a Piecewise from ``where(c, a, b)`` or ``piecewise(a1, c1, ..., default)``."""
        if swap:
            arguments = [arguments[1], arguments[0], arguments[2]]
        pieces, estimate, decided = [], None, False
        for value_node, condition_node in zip(arguments[:-1:2], arguments[1::2]):
            value, condition = self.value(value_node), self.condition(condition_node)
            pieces.append((value.expr, condition.expr))
            if not decided and condition.estimate is not False:
                decided = True
                estimate = value.estimate if condition.estimate else None
        default = self.value(arguments[-1])
        pieces.append((default.expr, sympy.true))
        if not decided:
            estimate = default.estimate
        return _Value(sympy.Piecewise(*pieces), estimate)

    # -- conditions ---------------------------------------------------------------------
    def condition(self, node: ast.AST) -> _Condition:
        """Convert a comparison, or ``and``/``or``/``not`` of comparisons."""
        if isinstance(node, ast.Compare):
            return self.compare(node)
        if isinstance(node, ast.BoolOp):
            parts = [self.condition(value) for value in node.values]
            estimates = [part.estimate for part in parts]
            if isinstance(node.op, ast.And):
                build = sympy.And
                estimate = False if False in estimates else (None if None in estimates else True)
            else:
                build = sympy.Or
                estimate = True if True in estimates else (None if None in estimates else False)
            return _Condition(build(*[part.expr for part in parts]), estimate)
        if isinstance(node, ast.UnaryOp) and isinstance(node.op, ast.Not):
            inner = self.condition(node.operand)
            estimate = None if inner.estimate is None else not inner.estimate
            return _Condition(sympy.Not(inner.expr), estimate)
        if isinstance(node, (ast.BinOp, ast.UnaryOp, ast.Constant, ast.Name, ast.Call)):
            self.value(node)  # report what is wrong inside first, if anything
            self.refuse(node, f"value '{self.source.segment(node)}' where a condition is "
                        "expected", "write a comparison such as t < 1")
        self.refuse_syntax(node)

    def compare(self, node: ast.Compare) -> _Condition:
        left = self.value(node.left)
        parts, estimate = [], True
        for left_node, op, right_node in zip([node.left, *node.comparators], node.ops,
                                             node.comparators):
            start, stop = self.source.end(left_node), self.source.start(right_node)
            if type(op) in _REFUSED_COMPARISONS:
                symbol = _REFUSED_COMPARISONS[type(op)]
                self.refuse(self.source.find(symbol, start, stop),
                            f"comparison '{symbol}' is not allowed", "use <, <=, > or >=")
            _, build, compute = _COMPARISONS[type(op)]
            right = self.value(right_node)
            parts.append(build(left.expr, right.expr))
            if estimate is not None and None not in (left.estimate, right.estimate):
                estimate = estimate and compute(left.estimate, right.estimate)
            else:
                estimate = None
            left = right
        return _Condition(sympy.And(*parts), estimate)


def _suggest(name: str, known, label: str) -> str:
    """``"did you mean 'EI'?"``, or the list of allowed names when nothing is close."""
    known = sorted(set(known))
    by_case = [candidate for candidate in known if candidate.lower() == name.lower()]
    close = by_case or difflib.get_close_matches(name, known, n=1, cutoff=0.6)
    if close:
        return f"did you mean '{close[0]}'?"
    shown = ", ".join(known[:15]) + (", ..." if len(known) > 15 else "")
    return f"{label}: {shown}" if known else f"no {label} here"


def _convert(text: object, names: Mapping[str, sympy.Expr], path: str, as_condition: bool):
    if not isinstance(names, Mapping):
        raise TypeError(f"names must be a mapping of names to SymPy symbols, not {type(names)}")
    if not isinstance(text, str):
        raise ModelError(path, "a condition written as text, e.g. 't < 1'" if as_condition
                         else "a number or an expression written as text", text)
    if len(text) > MAX_LENGTH:
        raise ModelError(path, f"an expression of at most {MAX_LENGTH} characters",
                         _shorten(text), f"it has {len(text)}; define parts of it as parameters")
    source = _Source(text)
    if not source.body.strip():
        raise ModelError(path, "an expression", text, "the text is empty")
    tree = _syntax_tree(text, source, path)
    converter = _Converter(text, source, names, path)
    _check_size(tree, converter.refuse)
    try:
        if as_condition:
            return converter.condition(tree.body).expr
        return converter.value(tree.body).expr
    except ModelError:
        raise
    except (TypeError, ValueError, ArithmeticError, RecursionError) as exc:
        raise ModelError(path, _EXPECTED, _shorten(text),
                         f"it could not be evaluated: {_shorten(str(exc), 120)}") from None


def parse_expression(text: object, names: Mapping[str, sympy.Expr], *, path: str) -> sympy.Expr:
    """Convert a number or the text of an expression into a SymPy expression.

    Parameters
    ----------
    text : int, float or str
        A finite number, or an expression in the language of this module.
    names : Mapping[str, sympy.Symbol]
        The names the expression may use, e.g. ``{"t": t}`` and the model's parameters.
    path : str
        Key path of the field, for error messages, e.g. ``"loads.push.force[0]"``.

    Returns
    -------
    sympy.Expr
        The expression; numbers give ``sympy.Integer`` or ``sympy.Float``.

    Raises
    ------
    ModelError
        For anything outside the language or its limits, naming the offending token and its
        column, and for an expression that is undefined (e.g. a division by zero).
    """
    if isinstance(text, bool) or not isinstance(text, (numbers.Real, str)):
        raise ModelError(path, "a number or an expression written as text", text,
                         "true and false are not numbers" if isinstance(text, bool) else None)
    if isinstance(text, numbers.Integral):
        if abs(int(text)) > MAX_INTEGER:
            raise ModelError(path, f"an integer of absolute value at most {MAX_INTEGER:.0e}",
                             text, "write large numbers in floating point, e.g. 1e20")
        return sympy.Integer(int(text))
    if isinstance(text, numbers.Real):
        if not math.isfinite(float(text)):
            raise ModelError(path, "a finite number", text)
        return sympy.Float(float(text))
    expr = _convert(text, names, path, as_condition=False)
    if expr.has(sympy.nan, sympy.zoo, sympy.oo, -sympy.oo):
        raise ModelError(path, _EXPECTED, _shorten(text),
                         "its value is undefined or infinite, e.g. a division by zero")
    return expr


def parse_condition(text: object, names: Mapping[str, sympy.Expr], *, path: str) -> sympy.Basic:
    """Convert the text of a condition (e.g. ``"0 < t < 1 and not x > 2"``) into SymPy.

    Parameters
    ----------
    text : str
        Comparisons ``< <= > >=`` of expressions, combined with ``and``, ``or``, ``not``.
    names : Mapping[str, sympy.Symbol]
        The names the condition may use.
    path : str
        Key path of the field, for error messages.

    Returns
    -------
    sympy.logic.boolalg.Boolean
        The condition (``sympy.true`` or ``sympy.false`` when it is decided by constants).
    """
    return _convert(text, names, path, as_condition=True)


def free_names(expr: sympy.Basic) -> set[str]:
    """Return the names of the symbols an expression depends on."""
    return {symbol.name for symbol in expr.free_symbols if isinstance(symbol, sympy.Symbol)}


_FLOAT_FUNCTIONS = {sympy_function: float_function
                    for sympy_function, float_function in (*_UNARY.values(), *_VARIADIC.values())}
_RELATIONS = {"<": operator.lt, "<=": operator.le, ">": operator.gt, ">=": operator.ge,
              "==": operator.eq, "!=": operator.ne}


def _evaluate(expr: sympy.Basic, values: Mapping[sympy.Symbol, float]):
    """Evaluate an expression or a condition in floating point (raises on domain errors)."""
    if expr.is_Symbol:
        return float(values[expr])
    if expr.is_Number or isinstance(expr, sympy.NumberSymbol):
        return float(expr)
    if expr is sympy.true or expr is sympy.false:
        return bool(expr)
    args = expr.args
    if expr.is_Add:
        return math.fsum(_evaluate(arg, values) for arg in args)
    if expr.is_Mul:
        return math.prod(_evaluate(arg, values) for arg in args)
    if expr.is_Pow:
        result = _evaluate(args[0], values) ** _evaluate(args[1], values)
        if isinstance(result, complex):
            raise ValueError("a negative number to a fractional power")
        return result
    if isinstance(expr, sympy.Piecewise):
        for piece, condition in args:
            if _evaluate(condition, values):
                return _evaluate(piece, values)
        raise ValueError("no branch of a piecewise expression applies")
    if isinstance(expr, sympy.core.relational.Relational):
        return _RELATIONS[expr.rel_op](_evaluate(args[0], values), _evaluate(args[1], values))
    if isinstance(expr, (sympy.And, sympy.Or)):
        combine = all if isinstance(expr, sympy.And) else any
        return combine(_evaluate(arg, values) for arg in args)
    if isinstance(expr, sympy.Not):
        return not _evaluate(args[0], values)
    if isinstance(expr, sympy.ITE):  # SymPy may rewrite the conditions of a Piecewise with it
        return _evaluate(args[1] if _evaluate(args[0], values) else args[2], values)
    if isinstance(expr, sympy.logic.boolalg.BooleanFunction):
        return bool(expr.func(*[sympy.true if _evaluate(arg, values) else sympy.false
                                for arg in args]))
    if expr.func in _FLOAT_FUNCTIONS:
        arguments = [_evaluate(arg, values) for arg in args]
        if expr.func in (sympy.Min, sympy.Max):
            return _FLOAT_FUNCTIONS[expr.func](arguments)
        return _FLOAT_FUNCTIONS[expr.func](*arguments)
    number = complex(expr.func(*[sympy.Float(_evaluate(arg, values)) for arg in args]).evalf())
    if number.imag:
        raise ValueError(f"{expr.func.__name__}() is not real here")
    return number.real


def to_float(expr: object, values: Mapping[sympy.Symbol, float], *, path: str) -> float:
    """Evaluate an expression numerically, in floating point.

    Parameters
    ----------
    expr : sympy.Expr or float
        An expression from :func:`parse_expression`.
    values : Mapping[sympy.Symbol, float]
        Values of its symbols.
    path : str
        Key path of the field the expression comes from, for error messages.

    Returns
    -------
    float
        The value, finite.

    Raises
    ------
    ModelError
        If a symbol has no value, or the value is undefined, not real or not finite.
    """
    if isinstance(expr, bool) or not isinstance(expr, (numbers.Real, sympy.Basic)):
        raise ModelError(path, "a number or an expression", expr)
    if isinstance(expr, numbers.Real):
        result = float(expr)
    else:
        missing = sorted(symbol.name for symbol in expr.free_symbols if symbol not in values)
        if missing:
            raise ModelError(path, "an expression of names with known values",
                             _shorten(str(expr)),
                             "no value for " + ", ".join(repr(name) for name in missing))
        try:
            result = _evaluate(expr, values)
        except (ArithmeticError, ValueError, TypeError, KeyError) as exc:
            raise ModelError(path, "an expression with a finite real value", _shorten(str(expr)),
                             f"evaluating it failed: {exc or type(exc).__name__}") from None
    if not math.isfinite(result):
        raise ModelError(path, "an expression with a finite value", _shorten(str(expr)),
                         f"its value is {result}")
    return float(result)


def resolve_parameters(definitions: Mapping[str, object], *,
                       path_prefix: str = "parameters") -> dict[str, float]:
    """Evaluate parameter definitions that may refer to each other.

    Parameters
    ----------
    definitions : Mapping[str, int | float | str]
        Parameter name -> number or expression of other parameters and ``pi``
        (e.g. ``{"c": 0.1, "d": 0.2, "mR": 3, "Iz": "mR*(c**2 + d**2)/12"}``). Names are
        ASCII identifiers, neither Python keywords nor :data:`RESERVED_NAMES` nor ``t``.
    path_prefix : str
        Key path of the table, for error messages.

    Returns
    -------
    dict[str, float]
        The value of every parameter, in the order of ``definitions``.

    Raises
    ------
    ModelError
        For an invalid name or expression, an unknown name (``t`` included: parameters do
        not depend on time), or a circular definition (the message names the cycle).
    """
    if not isinstance(definitions, Mapping):
        raise ModelError(path_prefix, "a table of parameter definitions", definitions)

    def path_of(name: str) -> str:
        return f"{path_prefix}.{name}" if path_prefix else name

    symbols = {}
    for name in definitions:
        check_parameter_name(name, path_of(str(name)))
        symbols[name] = sympy.Symbol(name)
    exprs = {}
    for name, value in definitions.items():
        try:
            exprs[name] = parse_expression(value, symbols, path=path_of(name))
        except ModelError as exc:
            if not (exc.hint or "").startswith("unknown name 't'"):
                raise
            raise ModelError(exc.path, exc.expected, exc.given,
                             "parameters are constants: they cannot depend on time 't'") from None
    # each expression's free names are computed once: linear in the total size of the definitions
    position = {name: k for k, name in enumerate(definitions)}
    dependencies = {name: sorted(free_names(expr), key=position.__getitem__)
                    for name, expr in exprs.items()}
    values: dict[sympy.Symbol, float] = {}
    for name in dependency_order(dependencies, definitions, path_of):
        values[symbols[name]] = to_float(exprs[name], values, path=path_of(name))
    return {name: values[symbols[name]] for name in definitions}


# ------------------------------------------------------------------ symbolic work on user expressions
#: Largest number of terms :func:`bounded_expand` lets an expansion produce.
MAX_EXPANDED_TERMS = 2000
#: A part of an expression free of the variables is kept whole when expanding it would give more terms.
_MAX_CONSTANT_TERMS = 16


def expansion_terms(expr: sympy.Basic, limit: int = MAX_EXPANDED_TERMS) -> int:
    """Number of terms :func:`sympy.expand` would produce, estimated from above (capped at ``limit + 1``).

    A sum has the terms of its parts, a product the product of theirs, and an integer power ``n`` of
    a sum of ``k`` terms the multinomial count ``C(k + n - 1, n)``; the arguments of functions are
    expanded on their own and add their terms. The estimate costs one pass over the expression
    (shared subexpressions are counted once), so it is safe on any user expression.
    """
    cap = limit + 1
    seen: dict[sympy.Basic, tuple[int, int]] = {}   # expr -> (terms, work inside function arguments)

    def visit(node) -> tuple[int, int]:
        if node in seen:
            return seen[node]
        if not node.args or not isinstance(node, sympy.Expr):
            result = (1, 0)
        else:
            parts = [visit(arg) for arg in node.args]
            work = min(cap, sum(w for _, w in parts))
            if node.is_Add:
                terms = min(cap, sum(t for t, _ in parts))
            elif node.is_Mul:
                terms = 1
                for t, _ in parts:
                    terms = min(cap, terms * t)
            elif node.is_Pow and node.exp.is_Integer and abs(int(node.exp)) > 1:
                k, n = parts[0][0], abs(int(node.exp))
                terms = cap if k >= cap or n >= cap else min(cap, math.comb(k + n - 1, n))
            elif node.is_Pow:
                terms = parts[0][0]
            else:   # a function: its arguments are expanded inside it
                terms, work = 1, min(cap, work + sum(t for t, _ in parts))
            result = (terms, work)
        seen[node] = result
        return result

    terms, work = visit(expr)
    return min(cap, terms + work)


def bounded_expand(expr: sympy.Expr, variables, time: sympy.Symbol,
                   limit: int = MAX_EXPANDED_TERMS) -> sympy.Expr | None:
    """Expand an expression of the equations in its variables, never expanding user expressions.

    The parts of ``expr`` free of ``variables`` that depend on ``time`` (the time laws of loads and
    drivers, as the user wrote them) or whose own expansion would exceed a few terms are kept whole:
    they stand as opaque factors during the expansion and are put back unchanged afterwards. So a
    torque ``(t + sin(t) + 1)**100`` stays a power and costs nothing.

    Parameters
    ----------
    expr : sympy.Expr
        An expression of the equations of motion.
    variables : iterable of sympy.Symbol
        Symbols the expansion is about (coordinates, speeds, their derivatives).
    time : sympy.Symbol
        The time symbol t.
    limit : int
        Largest number of terms the expansion may produce.

    Returns
    -------
    sympy.Expr or None
        The expansion, or None when it would have more than ``limit`` terms.
    """
    variables = frozenset(variables)
    placeholders: dict[sympy.Basic, sympy.Dummy] = {}

    def masked(node):
        if not node.args or not isinstance(node, sympy.Expr):
            return node
        free = node.free_symbols
        if not free & variables and (time in free or expansion_terms(node, _MAX_CONSTANT_TERMS)
                                     > _MAX_CONSTANT_TERMS):
            if node not in placeholders:
                placeholders[node] = sympy.Dummy("user", real=True)
            return placeholders[node]
        return node.func(*[masked(arg) for arg in node.args])

    opaque = masked(expr)
    if expansion_terms(opaque, limit) > limit:
        return None
    expanded = sympy.expand(opaque)
    return expanded.xreplace({dummy: node for node, dummy in placeholders.items()})


def _branch_sign(x: sympy.Expr) -> sympy.Expr:
    """``1`` where ``x >= 0``, ``-1`` elsewhere: the derivative of ``abs`` over that of its argument."""
    return sympy.Piecewise((sympy.Integer(1), x >= 0), (sympy.Integer(-1), True))


def _extreme_derivative(args, derivatives, better) -> sympy.Expr:
    """Derivative of ``max`` (``better`` is ``>=``) or ``min`` (``<=``): that of the first argument
    at least as good as every later one."""
    pieces = [(d, sympy.And(*[better(a, b) for b in args[k + 1:]]))
              for k, (a, d) in enumerate(zip(args[:-1], derivatives[:-1]))]
    return sympy.Piecewise(*pieces, (derivatives[-1], True))


def _branch_derivative(expr: sympy.Expr, time: sympy.Symbol) -> sympy.Expr:
    """``d expr / d time`` by the chain rule, node by node with memory: each distinct subexpression is
    differentiated once, and ``abs``, ``min``, ``max`` and ``piecewise`` branch by branch with their
    arguments left as they are (no argument is copied into conditions and values), so the derivative of
    six nested ``abs`` has a size linear in the nesting where rewriting each ``abs(x)`` as
    ``piecewise(x, x >= 0, -x)`` before differentiating tripled the expression per level."""
    memo: dict = {}

    def d(node):
        if node in memo:
            return memo[node]
        if not node.has(time):
            out = sympy.Integer(0)
        elif node == time:
            out = sympy.Integer(1)
        elif isinstance(node, sympy.Abs):
            out = _branch_sign(node.args[0]) * d(node.args[0])
        elif isinstance(node, (sympy.Max, sympy.Min)):
            args = list(node.args)
            better = (lambda a, b: a >= b) if isinstance(node, sympy.Max) else (lambda a, b: a <= b)
            out = _extreme_derivative(args, [d(a) for a in args], better)
        elif isinstance(node, sympy.Piecewise):
            out = sympy.Piecewise(*[(d(e), c) for e, c in node.args])
        elif isinstance(node, sympy.Add):
            out = sympy.Add(*[d(a) for a in node.args])
        elif isinstance(node, sympy.Mul):
            args = node.args
            out = sympy.Add(*[sympy.Mul(*args[:k], d(a), *args[k + 1:]) for k, a in enumerate(args) if a.has(time)])
        elif isinstance(node, sympy.Pow) and not node.exp.has(time):
            out = node.exp * node.base ** (node.exp - 1) * d(node.base)
        elif isinstance(node, sympy.Pow):
            out = node * (d(node.exp) * sympy.log(node.base) + node.exp * d(node.base) / node.base)
        elif isinstance(node, sympy.Function) and len(node.args) == 1:
            dummy = sympy.Dummy("u", real=True)
            out = sympy.diff(node.func(dummy), dummy).xreplace({dummy: node.args[0]}) * d(node.args[0])
        else:
            out = sympy.diff(node, time)
        memo[node] = out
        return out

    return d(expr)


def time_derivative(expr: sympy.Expr, time: sympy.Symbol, *, path: str, order: int = 1) -> sympy.Expr:
    """Derivative of a time law (a driver's coordinate or speed) with respect to time.

    ``abs``, ``min``, ``max``, ``where`` and ``piecewise`` are differentiated branch by branch: the
    derivative of ``abs(x)`` is ``x'`` where ``x >= 0`` and ``-x'`` elsewhere, that of ``max(a, b)``
    is ``a'`` where ``a >= b`` and ``b'`` elsewhere, that of ``where(c, a, b)`` is
    ``where(c, a', b')``. At a kink the derivative is that of the branch whose condition holds there
    (the first one of ``piecewise``): a one-sided derivative, never an impulse.

    Parameters
    ----------
    expr : sympy.Expr
        The law, an expression of t and parameters.
    time : sympy.Symbol
    path : str
        Key path of the field, for the message when the law cannot be differentiated.
    order : int
        Order of the derivative.

    Returns
    -------
    sympy.Expr
        The derivative, free of ``DiracDelta``, ``Heaviside`` and unevaluated derivatives.
    """
    result = expr
    for _ in range(order):
        result = _branch_derivative(result, time)
    if result.has(sympy.DiracDelta, sympy.Heaviside, sympy.Derivative, sympy.Subs, sympy.sign):
        raise ModelError(path, "a time law that can be differentiated with respect to t", _shorten(str(expr)),
                         f"its derivative of order {order} is not a function of t")
    return result
