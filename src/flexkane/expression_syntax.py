"""The expression language of model files without SymPy: its limits, its parsing, and a float evaluator.

:mod:`flexkane.expressions` converts an expression into SymPy for the derivation. Validating a model
(``flexkane check``) only needs the value of each field, so this module provides what both share and
needs no SymPy: the limits (:data:`MAX_LENGTH`, :data:`MAX_NODES`, :data:`MAX_DEPTH`, ...), the names of
the language (:data:`FUNCTIONS`, :data:`RESERVED_NAMES`), the parse into a syntax tree with its size
check, the order of parameter definitions; and :func:`simple_value`, the value of an expression in
floating point straight from its syntax tree.

:func:`simple_value` answers only where the SymPy conversion would accept the expression and give the
same value: an expression within the limits, written in the language, whose constant parts are
computed as the conversion computes them, and in which SymPy can neither cancel nor combine anything
(no name, constant ``pi`` or function appears twice within one algebraic term, no power of a power
beyond :data:`MAX_EXPONENT`, no exponent that is not a number, no function of a constant, no ``exp``
of a logarithm). Everything else (and every error) raises :class:`NeedsSymbolic`: the caller then
converts the expression with :func:`flexkane.expressions.parse_expression`, which gives today's answer
and message. So the checks of the language run once, in one place, whichever way a value is computed.
"""

from __future__ import annotations

import ast
import bisect
import keyword
import math
import numbers
import operator
import re
import warnings
from collections.abc import Mapping
from fractions import Fraction

from .errors import ModelError

__all__ = ["FUNCTIONS", "MAX_DEPTH", "MAX_EXPONENT", "MAX_INTEGER", "MAX_LENGTH", "MAX_NODES",
           "NeedsSymbolic", "RESERVED_NAMES", "check_parameter_name", "dependency_order",
           "expression_names", "may_be_unbounded", "rename_names", "simple_names", "simple_value"]

MAX_LENGTH = 2000  #: Maximum number of characters of an expression.
MAX_NODES = 500  #: Maximum number of syntax elements (numbers, names, operations, calls).
MAX_DEPTH = 50  #: Maximum nesting depth; a chain ``a + b - c + ...`` counts as one level.
MAX_INTEGER = 10**15  #: Largest absolute value of an integer literal.
MAX_EXPONENT = 100  #: Largest absolute value of a numeric exponent.
_MAX_COEFFICIENT_BITS = 4096  # largest numeric coefficient SymPy may compute in a power

#: Functions of one argument, of two or more (``min``, ``max``), and the branch functions.
UNARY_FUNCTIONS = ("sin", "cos", "tan", "exp", "log", "sqrt", "sinh", "cosh", "tanh", "abs")
VARIADIC_FUNCTIONS = ("min", "max")
#: Names of the functions an expression may call.
FUNCTIONS = tuple(sorted([*UNARY_FUNCTIONS, *VARIADIC_FUNCTIONS, "where", "piecewise"]))
#: Names that an expression always reads as functions or constants.
RESERVED_NAMES = frozenset([*FUNCTIONS, "pi"])

_EXPECTED = ("an expression of numbers, names, + - * / ** and the functions "
             + " ".join(FUNCTIONS))
_BINARY = {ast.Add: "+", ast.Sub: "-", ast.Mult: "*", ast.Div: "/", ast.Pow: "**",
           ast.Mod: "%", ast.FloorDiv: "//", ast.MatMult: "@", ast.LShift: "<<",
           ast.RShift: ">>", ast.BitOr: "|", ast.BitXor: "^", ast.BitAnd: "&"}
_ADDITIVE = (ast.Add, ast.Sub)
_MULTIPLICATIVE = (ast.Mult, ast.Div)
_OPERATOR_NODES = (ast.expr_context, ast.operator, ast.unaryop, ast.cmpop, ast.boolop)
_NEWLINE = re.compile(r"\r\n|\r|\n")


def _shorten(text: str, limit: int = 80) -> str:
    return text if len(text) <= limit else text[: limit - 3] + "..."



class _Source:
    """The text of an expression, with the bookkeeping needed to report columns."""

    def __init__(self, text: str):
        self.body = text.lstrip(" \t\f\r\n")
        prefix_lines = _NEWLINE.split(text[: len(text) - len(self.body)])
        self.line_shift = len(prefix_lines) - 1
        self.column_shift = len(prefix_lines[-1])
        self.multiline = _NEWLINE.search(text) is not None
        self.lines = _NEWLINE.split(self.body)
        self.starts = [0] + [match.end() for match in _NEWLINE.finditer(self.body)]

    def index(self, lineno: int | None, byte_column: int | None) -> int:
        """Character index in the body of an AST position (line from 1, column in UTF-8 bytes)."""
        if not lineno or not 0 < lineno <= len(self.lines):
            return 0
        line = self.lines[lineno - 1].encode("utf-8")[: byte_column or 0]
        return self.starts[lineno - 1] + len(line.decode("utf-8", "replace"))

    def start(self, node: ast.AST) -> int:
        return self.index(getattr(node, "lineno", None), getattr(node, "col_offset", None))

    def end(self, node: ast.AST) -> int:
        return self.index(getattr(node, "end_lineno", None), getattr(node, "end_col_offset", None))

    def segment(self, node: ast.AST) -> str:
        return _shorten(self.body[self.start(node): self.end(node)], 40)

    def find(self, symbol: str, start: int, end: int) -> int:
        """Index of ``symbol`` between two indices (``start`` when absent)."""
        found = self.body.find(symbol, start, end)
        return start if found < 0 else found

    def where(self, index: int) -> str:
        """``"column C"`` (``"line L, column C"`` for text of several lines), counted from 1."""
        line = bisect.bisect_right(self.starts, index) - 1
        column = index - self.starts[line] + (self.column_shift if line == 0 else 0)
        if self.multiline:
            return f"line {line + self.line_shift + 1}, column {column + 1}"
        return f"column {column + 1}"


def _syntax_tree(text: str, source: _Source, path: str) -> ast.Expression:
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return ast.parse(source.body, mode="eval")
    except SyntaxError as exc:
        lineno = exc.lineno if exc.lineno and exc.lineno <= len(source.lines) else None
        index = source.starts[lineno - 1] + max((exc.offset or 1) - 1, 0) if lineno else 0
        where = source.where(min(index, len(source.body)))
        hint = f"syntax error at {where}: {exc.msg}"
    except (ValueError, RecursionError, MemoryError) as exc:
        hint = f"syntax error: {exc}"
    raise ModelError(path, _EXPECTED, _shorten(text), hint)


def _check_size(tree: ast.Expression, refuse):
    """Refuse a tree with too many elements or nested too deeply (before converting it).

    ``refuse(node, what, hint)`` reports the problem (it raises).
    """
    count, stack = 0, [(tree.body, 1)]
    while stack:
        node, depth = stack.pop()
        count += 1
        if count > MAX_NODES:
            refuse(node, f"more than {MAX_NODES} elements",
                   "define parts of the expression as parameters")
        if depth > MAX_DEPTH:
            refuse(node, f"nesting deeper than {MAX_DEPTH} levels")
        for child in ast.iter_child_nodes(node):
            if not isinstance(child, _OPERATOR_NODES):
                same_chain = (isinstance(node, ast.BinOp) and child is node.left
                              and isinstance(child, ast.BinOp)
                              and any(isinstance(node.op, kinds) and isinstance(child.op, kinds)
                                      for kinds in (_ADDITIVE, _MULTIPLICATIVE)))
                stack.append((child, depth if same_chain else depth + 1))



def dependency_order(dependencies: dict[str, list[str]], definitions, path_of) -> list[str]:
    """Order names so that each comes after what it depends on; refuse a cycle."""
    order, state = [], {}  # state: 1 while on the current path, 2 when done
    for root in dependencies:
        if state.get(root):
            continue
        path, stack = [root], [iter(dependencies[root])]
        state[root] = 1
        while stack:
            child = next(stack[-1], None)
            if child is None:
                stack.pop()
                done = path.pop()
                state[done] = 2
                order.append(done)
            elif state.get(child) == 1:
                cycle = path[path.index(child):] + [child]
                raise ModelError(path_of(child), "parameter definitions without a cycle",
                                 definitions[child], "cycle: " + " -> ".join(cycle))
            elif not state.get(child):
                state[child] = 1
                path.append(child)
                stack.append(iter(dependencies[child]))
    return order


def check_parameter_name(name, path: str) -> None:
    """Refuse a parameter name that is not an identifier, or is a keyword, a reserved name or ``t``."""
    if not isinstance(name, str) or not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", name) \
            or keyword.iskeyword(name):
        raise ModelError(path, "a parameter name made of ASCII letters, digits "
                         "and underscores, not starting with a digit", name)
    if name in RESERVED_NAMES or name == "t":
        raise ModelError(path, "a parameter name that is not reserved", name,
                         f"'{name}' is " + ("time" if name == "t" else "a built-in name"))


# ------------------------------------------------------------------ values without SymPy
class NeedsSymbolic(Exception):
    """The expression needs the SymPy conversion: it may be refused, or SymPy may simplify it."""


_OPAQUE = frozenset(["sin", "cos", "tan", "sinh", "cosh", "tanh", "min", "max", "where", "piecewise"])
_FLOAT_UNARY = {"sin": math.sin, "cos": math.cos, "tan": math.tan, "exp": math.exp, "log": math.log,
                "sqrt": lambda x: x ** 0.5, "sinh": math.sinh, "cosh": math.cosh, "tanh": math.tanh,
                "abs": abs}
_ORDER = {ast.Lt: operator.lt, ast.LtE: operator.le, ast.Gt: operator.gt, ast.GtE: operator.ge}
_ARITHMETIC = {ast.Add: operator.add, ast.Sub: operator.sub, ast.Mult: operator.mul, ast.Div: operator.truediv}
#: A sum (or a comparison) whose result is this small relative to its terms is left to SymPy, whose exact
#: arithmetic may decide its sign differently.
_CANCELLATION = 1e-9


def _give_up(*_args, **_kwargs):
    raise NeedsSymbolic


def _finite(value) -> float:
    if isinstance(value, complex) or not math.isfinite(value):
        raise NeedsSymbolic
    return float(value)


def _has(node: ast.AST, kind, name: str | None = None) -> bool:
    return any(isinstance(n, kind) and (name is None or getattr(getattr(n, "func", None), "id", None) == name)
               for n in ast.walk(node))


def _branches(node: ast.AST) -> bool:
    """Whether ``node`` has a ``where`` or ``piecewise``."""
    return _has(node, ast.Call, "where") or _has(node, ast.Call, "piecewise")


def _named(node: ast.AST) -> bool:
    """Whether ``node`` uses a name other than ``pi`` (whether it is not a constant)."""
    functions = {id(n.func) for n in ast.walk(node) if isinstance(n, ast.Call)}
    return any(isinstance(n, ast.Name) and n.id != "pi" and id(n) not in functions for n in ast.walk(node))


def _literal_bits(node: ast.AST) -> int:
    """An upper bound of the bits of the numeric coefficient SymPy may extract from ``node``."""
    bits = 0
    for n in ast.walk(node):
        if isinstance(n, ast.Constant) and isinstance(n.value, (int, float)):
            value = abs(n.value)
            bits += int(value).bit_length() if isinstance(n.value, int) else abs(math.frexp(value)[1]) + 1
    return bits


class _Scan:
    """Check that an expression is simple (see the module docstring); fold its constant parts.

    Each method returns ``(float, Fraction or None)`` for a constant part, None for a part with names.
    """

    def __init__(self, names):
        self.names, self.used = names, set()

    def atom(self, level: dict, key: str, scale: float):
        level[key] = level.get(key, 0) + 1
        if level[key] > 1 or scale > MAX_EXPONENT:
            raise NeedsSymbolic

    def value(self, node, level: dict, scale: float):
        if isinstance(node, ast.Constant):
            number = node.value
            if isinstance(number, bool) or not isinstance(number, (int, float)):
                raise NeedsSymbolic
            if isinstance(number, int):
                if abs(number) > MAX_INTEGER:
                    raise NeedsSymbolic
                return float(number), Fraction(number)
            return _finite(number), None
        if isinstance(node, ast.Name):
            if node.id != "pi" and node.id not in self.names:
                raise NeedsSymbolic
            self.atom(level, node.id, scale)
            if node.id != "pi":
                self.used.add(node.id)
            return None
        if isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.USub, ast.UAdd)):
            inner = self.value(node.operand, level, scale)
            if inner is None or isinstance(node.op, ast.UAdd):
                return inner
            return -inner[0], None if inner[1] is None else -inner[1]
        if isinstance(node, ast.BinOp) and type(node.op) in _ARITHMETIC:
            if isinstance(node.op, ast.Div) and _branches(node.right):
                raise NeedsSymbolic
            if isinstance(node.op, _MULTIPLICATIVE):
                named = [_named(node.left), _named(node.right)]
                left = self.factor(node.left, level, scale, own=named[1])
                right = self.factor(node.right, level, scale, own=named[0] or isinstance(node.op, ast.Div))
            else:
                left, right = self.value(node.left, level, scale), self.value(node.right, level, scale)
            constants = [part for part in (left, right) if part is not None]
            if isinstance(node.op, (ast.Mult, ast.Div)) and any(part[0] == 0 for part in constants):
                raise NeedsSymbolic   # SymPy drops what a zero multiplies; a division by zero is refused
            if left is None or right is None:
                return None
            return self.fold(_ARITHMETIC[type(node.op)], left, right)
        if isinstance(node, ast.BinOp) and isinstance(node.op, ast.Pow):
            exponent = self.value(node.right, {}, 1.0)
            if exponent is None or exponent[0] == 0 or abs(exponent[0]) > MAX_EXPONENT:
                raise NeedsSymbolic
            if not _named(node.left):
                base = self.value(node.left, level, scale)
                if base is None:   # a power of pi
                    raise NeedsSymbolic
                if exponent[1] is None or exponent[1].denominator != 1:
                    raise NeedsSymbolic   # SymPy may find an exact root
                if base[1] is not None and _magnitude(base[1]) * abs(exponent[0]) > _MAX_COEFFICIENT_BITS:
                    raise NeedsSymbolic
                return self.fold(operator.pow, base, exponent)
            if _literal_bits(node.left) * abs(exponent[0]) > _MAX_COEFFICIENT_BITS:
                raise NeedsSymbolic
            if _branches(node.left):
                raise NeedsSymbolic   # SymPy takes a power into the branches of a piecewise
            # SymPy combines powers of powers from the inside out: an outer root does not undo them
            self.factor(node.left, level, scale * max(1.0, abs(exponent[0])), own=True)
            return None
        if isinstance(node, ast.Call):
            return self.call(node, level, scale)
        raise NeedsSymbolic

    def factor(self, node, level: dict, scale: float, own: bool):
        """A factor of a product or the base of a power: with ``own``, a sum is a term of its own.

        SymPy distributes only a numeric coefficient over a sum (``2*(x + y)``); a sum multiplied by
        names, divided into, or raised to a power stays whole, so its names cannot meet those around
        it. It is then one atom of the product (named by the names inside: ``(x+1)*(1+x)`` combines).
        """
        if not (own and isinstance(node, ast.BinOp) and isinstance(node.op, _ADDITIVE)):
            return self.value(node, level, scale)
        inner: dict = {}
        result = self.value(node, inner, scale)
        if result is None:
            self.atom(level, "(" + ",".join(sorted(inner)) + ")", scale)
        return result

    def fold(self, function, left, right):
        try:
            estimate = _finite(function(left[0], right[0]))
            exact = None
            if left[1] is not None and right[1] is not None:
                exact = function(left[1], right[1])
                if not isinstance(exact, Fraction) or _magnitude(exact) > _MAX_COEFFICIENT_BITS:
                    raise NeedsSymbolic
        except (ArithmeticError, ValueError, TypeError):
            raise NeedsSymbolic from None
        return estimate, exact

    def call(self, node: ast.Call, level: dict, scale: float):
        name = node.func.id if isinstance(node.func, ast.Name) else None
        count = len(node.args)
        if name not in FUNCTIONS or node.keywords or any(isinstance(a, ast.Starred) for a in node.args) \
                or not _named(node) or (name in _FLOAT_UNARY and count != 1) \
                or (name in VARIADIC_FUNCTIONS and count < 2) or (name == "where" and count != 3) \
                or (name == "piecewise" and (count < 3 or count % 2 == 0)):
            raise NeedsSymbolic   # a function of constants, or a refused call
        if name in _FLOAT_UNARY and not _named(node.args[0]):
            raise NeedsSymbolic
        self.atom(level, name, scale)
        if name == "exp" and _has(node.args[0], ast.Call, "log"):
            raise NeedsSymbolic
        if name in ("sin", "cos", "tan") and any(not _named(term) and _has(term, ast.Name)
                                                 for term, _ in _terms(node.args[0], 1.0)):
            raise NeedsSymbolic   # SymPy takes multiples of pi/2 out: sin(t - pi) = -sin(t)
        if name not in _OPAQUE:   # exp, log, sqrt, abs: SymPy may combine them with the term around
            self.value(node.args[0], level, scale)   # a root does not undo the powers inside
            return None
        conditions = set()
        if name == "where":
            conditions = {0}
        elif name == "piecewise":
            conditions = set(range(1, count - 1, 2))
        for k, argument in enumerate(node.args):
            if k in conditions:
                self.condition(argument)
            else:
                self.value(argument, {}, 1.0)
        return None

    def condition(self, node):
        if isinstance(node, ast.Compare):
            if any(type(op) not in _ORDER for op in node.ops):
                raise NeedsSymbolic
            level = {}
            for side in (node.left, *node.comparators):
                self.value(side, level, 1.0)
        elif isinstance(node, ast.BoolOp):
            for part in node.values:
                self.condition(part)
        elif isinstance(node, ast.UnaryOp) and isinstance(node.op, ast.Not):
            self.condition(node.operand)
        else:
            raise NeedsSymbolic


def _magnitude(number: Fraction) -> int:
    return max(abs(number.numerator).bit_length(), number.denominator.bit_length())


def _terms(node, sign: float):
    """The terms of a sum, with their signs, as SymPy flattens it."""
    if isinstance(node, ast.BinOp) and isinstance(node.op, _ADDITIVE):
        yield from _terms(node.left, sign)
        yield from _terms(node.right, -sign if isinstance(node.op, ast.Sub) else sign)
    elif isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.USub, ast.UAdd)):
        yield from _terms(node.operand, -sign if isinstance(node.op, ast.USub) else sign)
    else:
        yield node, sign


def _evaluate(node, env: Mapping[str, float]):
    """Float value of a checked tree (raises NeedsSymbolic on a near cancellation)."""
    if isinstance(node, ast.Constant):
        return float(node.value)
    if isinstance(node, ast.Name):
        return math.pi if node.id == "pi" else float(env[node.id])
    if isinstance(node, (ast.UnaryOp, ast.BinOp)) and isinstance(getattr(node, "op", None),
                                                                 (ast.USub, ast.UAdd, ast.Add, ast.Sub)):
        terms = [sign * _evaluate(term, env) for term, sign in _terms(node, 1.0)]
        total = math.fsum(terms)
        largest = max(abs(term) for term in terms)
        if len(terms) > 1 and largest > 0 and abs(total) <= _CANCELLATION * largest:
            raise NeedsSymbolic
        return total
    if isinstance(node, ast.BinOp):
        left, right = _evaluate(node.left, env), _evaluate(node.right, env)
        if isinstance(node.op, ast.Mult):
            return left * right
        if isinstance(node.op, ast.Div):
            return left * right ** -1.0
        if left == 0 and right != int(right):
            _no_negative_factor(node.left, env)
        return _finite(left ** right)
    if isinstance(node, ast.Call):
        name = node.func.id
        if name == "where":
            return _evaluate(node.args[1] if _condition(node.args[0], env) else node.args[2], env)
        if name == "piecewise":
            for value, condition in zip(node.args[:-1:2], node.args[1::2]):
                if _condition(condition, env):
                    return _evaluate(value, env)
            return _evaluate(node.args[-1], env)
        arguments = [_evaluate(argument, env) for argument in node.args]
        if name == "sqrt" and arguments[0] == 0:
            _no_negative_factor(node.args[0], env)
        if name in VARIADIC_FUNCTIONS:
            return (min if name == "min" else max)(arguments)
        return _finite(_FLOAT_UNARY[name](*arguments))
    raise NeedsSymbolic


def _no_negative_factor(node, env) -> None:
    """Hand over a root of a zero product with a negative factor: SymPy takes the factors it knows to be
    non-negative out of a root (sqrt(t**2*y) = abs(t)*sqrt(y)), and the root of what remains may not be real."""
    if isinstance(node, ast.BinOp) and isinstance(node.op, _MULTIPLICATIVE):
        _no_negative_factor(node.left, env)
        _no_negative_factor(node.right, env)
        return
    value = _evaluate(node, env)
    if math.copysign(1.0, value) < 0:
        raise NeedsSymbolic


def _condition(node, env) -> bool:
    if isinstance(node, ast.Compare):
        sides = [_evaluate(side, env) for side in (node.left, *node.comparators)]
        for (left, right), op in zip(zip(sides, sides[1:]), node.ops):
            if (left or right) and abs(left - right) <= _CANCELLATION * max(abs(left), abs(right)):
                raise NeedsSymbolic   # SymPy may decide an equality symbolically
            if not _ORDER[type(op)](left, right):
                return False
        return True
    if isinstance(node, ast.BoolOp):
        combine = all if isinstance(node.op, ast.And) else any
        return combine(_condition(part, env) for part in node.values)
    return not _condition(node.operand, env)


def _checked_tree(text) -> ast.Expression:
    """The syntax tree of ``text`` checked against the language's syntax and limits; raises
    :class:`NeedsSymbolic` for anything else (the SymPy conversion then says why)."""
    if isinstance(text, bool) or not isinstance(text, str) or len(text) > MAX_LENGTH:
        raise NeedsSymbolic
    source = _Source(text)
    if not source.body.strip():
        raise NeedsSymbolic
    try:
        tree = _syntax_tree(text, source, "")
    except ModelError:
        raise NeedsSymbolic from None
    _check_size(tree, _give_up)
    return tree


def _simple_tree(text, names) -> tuple[ast.AST, set[str]]:
    """The checked syntax tree of a simple expression and the names it uses."""
    tree = _checked_tree(text)
    scan = _Scan(names)
    scan.value(tree.body, {}, 1.0)
    return tree.body, scan.used


def expression_names(text) -> set[str]:
    """The names an expression uses (functions and ``pi`` excepted), from its syntax alone.

    Raises :class:`NeedsSymbolic` when the text is not within the language's syntax and limits (the
    SymPy conversion, :func:`flexkane.expressions.parse_expression`, then says why).
    """
    if isinstance(text, numbers.Real) and not isinstance(text, bool):
        return set()
    tree = _checked_tree(text)
    called = {id(node.func) for node in ast.walk(tree) if isinstance(node, ast.Call)}
    return {node.id for node in ast.walk(tree)
            if isinstance(node, ast.Name) and id(node) not in called and node.id != "pi"}


def _constant_number(node) -> float | None:
    """The value of a syntax tree of numbers alone (``1/7``, ``-2``), else None."""
    if isinstance(node, ast.Constant) and isinstance(node.value, (int, float)) and not isinstance(node.value, bool):
        return float(node.value)
    if isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.UAdd, ast.USub)):
        value = _constant_number(node.operand)
        return None if value is None else (value if isinstance(node.op, ast.UAdd) else -value)
    if isinstance(node, ast.BinOp) and isinstance(node.op, (ast.Add, ast.Sub, ast.Mult, ast.Div)):
        a, b = _constant_number(node.left), _constant_number(node.right)
        if a is None or b is None or (isinstance(node.op, ast.Div) and b == 0):
            return None
        return {ast.Add: a + b, ast.Sub: a - b, ast.Mult: a * b}.get(type(node.op), a / b if b else None)
    return None


def may_be_unbounded(text, name: str) -> bool:
    """Whether an expression may be unbounded where the variable ``name`` is finite, from its syntax.

    An expression built of numbers, names, sums, products, non-negative numeric powers and the functions
    other than ``tan`` and ``log`` is bounded wherever its names are: it may be unbounded only through a
    division by, a negative or non-numeric power of, or a ``tan`` or ``log`` of something that depends on
    ``name``. Used to decide whether a distributed load needs the search for poles along its beam
    (:mod:`flexkane.model.load_integrability`) without SymPy.

    Parameters
    ----------
    text : str or number
        The expression.
    name : str
        The variable (``"x"``, the position along a beam [m]).

    Returns
    -------
    bool
        True when such a construct depends on ``name``, and for a text outside the language's syntax
        and limits (its conversion then decides); False when the expression is bounded for finite ``name``.
    """
    if isinstance(text, numbers.Real) and not isinstance(text, bool):
        return False
    try:
        tree = _checked_tree(text)
    except NeedsSymbolic:
        return True

    def depends(node) -> bool:
        return any(isinstance(n, ast.Name) and n.id == name for n in ast.walk(node))

    for node in ast.walk(tree):
        if isinstance(node, ast.BinOp) and isinstance(node.op, (ast.Div, ast.FloorDiv, ast.Mod)) \
                and depends(node.right):
            return True
        if isinstance(node, ast.BinOp) and isinstance(node.op, ast.Pow) and depends(node):
            exponent = _constant_number(node.right)
            if exponent is None or exponent < 0:
                return True
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id in ("tan", "log") \
                and any(depends(arg) for arg in node.args):
            return True
    return False


def rename_names(text, names: Mapping[str, str]):
    """``text`` with each name that ``names`` maps replaced by its new name, every other character
    kept (functions and ``pi`` are never renamed).

    A number, or a text outside the language's syntax and limits, is returned unchanged (its
    validation then says what is wrong with it).
    """
    if not isinstance(text, str):
        return text
    try:
        tree = _checked_tree(text)
    except NeedsSymbolic:
        return text
    source = _Source(text)
    called = {id(node.func) for node in ast.walk(tree) if isinstance(node, ast.Call)}
    spans = sorted(((source.start(node), source.end(node), names[node.id]) for node in ast.walk(tree)
                    if isinstance(node, ast.Name) and id(node) not in called and node.id in names), reverse=True)
    body = source.body
    for start, end, new in spans:
        body = body[:start] + new + body[end:]
    return text[: len(text) - len(source.body)] + body


def simple_names(text, names) -> set[str]:
    """The names a simple expression uses, among ``names`` (raises :class:`NeedsSymbolic`)."""
    if isinstance(text, numbers.Real) and not isinstance(text, bool):
        return set()
    return _simple_tree(text, names)[1]


def simple_value(text, values: Mapping[str, float]) -> float:
    """The value of a number or of a simple expression, without SymPy.

    Parameters
    ----------
    text : int, float or str
        A field of a model: a number or the text of an expression.
    values : Mapping[str, float]
        Values of the names it may use (parameters, ``t``, ``x``).

    Returns
    -------
    float
        The value, finite; the same (to rounding) as ``to_float(parse_expression(text, ...), ...)``.

    Raises
    ------
    NeedsSymbolic
        When the expression is not simple, is refused, or its value is not finite: convert it with
        :func:`flexkane.expressions.parse_expression` instead.
    """
    if isinstance(text, bool):
        raise NeedsSymbolic
    if isinstance(text, numbers.Integral):
        if abs(int(text)) > MAX_INTEGER:
            raise NeedsSymbolic
        return float(int(text))
    if isinstance(text, numbers.Real):
        return _finite(float(text))
    tree, _ = _simple_tree(text, values)
    try:
        return _finite(_evaluate(tree, values))
    except (ArithmeticError, ValueError, TypeError, KeyError, RecursionError):
        raise NeedsSymbolic from None
