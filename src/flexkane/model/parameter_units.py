"""Units of parameters read from the expressions that use them.

A field of a model has a unit (the one validation checks it in); a parameter that a field names
alone (``mass = "m1"``) has that unit. A parameter used only inside an expression, such as the
time laws of drivers and loads (``torque = "where(t < t1, T0*sin(2*pi*t/t1), 0)"`` [N m],
``driver = { coordinate = "Omega*t" }`` [rad]), gets its unit from the rules of dimensions: both
sides of a sum, a comparison and the branches of ``where`` have one unit, the arguments of sin,
cos, exp ... are dimensionless, t is in s and x in m. From ``Omega*t`` [rad]: Omega [rad/s]; from
``t < t1``: t1 [s], then ``T0*sin(...)`` [N m]: T0 [N m]. A unit is kept only where every use
agrees; a parameter whose unit no use fixes, or whose uses disagree, gets none.

Units are products of powers of the unit names as the fields write them (``N m``, ``rad/s``,
``kg m^2``, ``-`` for none); N is not reduced to kg m/s^2. The same rules give the units of
controller states and outputs (:func:`flexkane.run_manifest.units`): an output has the unit of its
expression and of the efforts it feeds, a state the unit of its rate times s.
"""

from __future__ import annotations

import ast
from fractions import Fraction

from ..expression_syntax import NeedsSymbolic, _checked_tree

__all__ = ["parse_unit", "format_unit", "field_values", "inferred_units"]

_DIMENSIONLESS = ("sin", "cos", "tan", "exp", "log", "sinh", "cosh", "tanh")
_SAME = ("abs", "min", "max")
_UNIT_NAMES = frozenset(["m", "kg", "s", "rad", "N", "J", "W", "Pa"])
_KNOWN_NAMES = {"t": {"s": Fraction(1)}, "x": {"m": Fraction(1)}, "pi": {}}


def parse_unit(text: str) -> dict | None:
    """``"N m/rad"`` -> ``{"N": 1, "m": 1, "rad": -1}`` (exponents as Fractions); ``"-"`` -> ``{}``;
    None for a text that is not such a product (``"rad or m"``)."""
    text = text.strip()
    if text == "-":
        return {}
    top, _, bottom = text.partition("/")
    if "/" in bottom:
        return None
    unit: dict = {}
    for sign, part in ((1, top), (-1, bottom)):
        for token in part.split():
            if token == "1" and sign == 1:
                continue
            name, _, power = token.partition("^")
            if name not in _UNIT_NAMES:
                return None
            try:
                exponent = Fraction(power) if power else Fraction(1)
            except ValueError:
                return None
            unit[name] = unit.get(name, 0) + sign * exponent
    return _clean(unit)


def format_unit(unit: dict) -> str:
    """The text of a unit (:func:`parse_unit` inverted): ``{"rad": 1, "s": -1}`` -> ``"rad/s"``."""
    def power(name, exponent):
        return name if exponent == 1 else f"{name}^{exponent}"

    top = " ".join(power(n, e) for n, e in unit.items() if e > 0)
    bottom = " ".join(power(n, -e) for n, e in unit.items() if e < 0)
    if not top and not bottom:
        return "-"
    return (top or "1") + (f"/{bottom}" if bottom else "")


def _clean(unit: dict) -> dict:
    return {n: e for n, e in sorted(unit.items()) if e != 0}


def _times(a: dict, b: dict, sign: int = 1) -> dict:
    out = dict(a)
    for n, e in b.items():
        out[n] = out.get(n, 0) + sign * e
    return _clean(out)


def _power(a: dict, exponent: Fraction) -> dict:
    return _clean({n: e * exponent for n, e in a.items()})


class _Inference:
    """One pass over the expressions, with the units found so far (``found``: name -> set of texts)."""

    def __init__(self, parameters, known: dict):
        self.parameters = parameters
        self.known = known          # parameter -> unit dict, decided
        self.found: dict = {}       # parameter -> list of unit dicts this pass

    def unit_of(self, node):
        """The unit of ``node`` when everything in it is known, else None."""
        if isinstance(node, ast.Constant):
            return {}
        if isinstance(node, ast.Name):
            if node.id in _KNOWN_NAMES:
                return _KNOWN_NAMES[node.id]
            return self.known.get(node.id)
        if isinstance(node, ast.UnaryOp):
            return self.unit_of(node.operand)
        if isinstance(node, ast.BinOp):
            if isinstance(node.op, (ast.Add, ast.Sub)):
                left = self.unit_of(node.left)
                return left if left is not None else self.unit_of(node.right)
            if isinstance(node.op, ast.Pow):
                base, exponent = self.unit_of(node.left), _number(node.right)
                return None if base is None or exponent is None else _power(base, exponent)
            left, right = self.unit_of(node.left), self.unit_of(node.right)
            if left is None or right is None:
                return None
            return _times(left, right, 1 if isinstance(node.op, ast.Mult) else -1)
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Name):
            name = node.func.id
            if name in _DIMENSIONLESS:
                return {}
            if name == "sqrt" and node.args:
                inner = self.unit_of(node.args[0])
                return None if inner is None else _power(inner, Fraction(1, 2))
            if name in ("where", "piecewise"):
                branches = node.args[1:] if name == "where" else node.args[0::2]
            else:
                branches = node.args
            for branch in branches:
                unit = self.unit_of(branch)
                if unit is not None:
                    return unit
        return None

    def expect(self, node, unit) -> None:
        """Walk ``node``, whose unit is ``unit`` (a dict, or None when unknown)."""
        if isinstance(node, ast.Name):
            if unit is not None and node.id in self.parameters and node.id not in _KNOWN_NAMES:
                self.found.setdefault(node.id, []).append(unit)
        elif isinstance(node, ast.UnaryOp):
            self.expect(node.operand, unit)
        elif isinstance(node, ast.BinOp):
            if isinstance(node.op, (ast.Add, ast.Sub)):
                unit = unit if unit is not None else self.unit_of(node)
                self.expect(node.left, unit)
                self.expect(node.right, unit)
            elif isinstance(node.op, ast.Pow):
                exponent = _number(node.right)
                self.expect(node.left, None if unit is None or not exponent else _power(unit, 1 / exponent))
                self.expect(node.right, {})
            else:
                left, right = self.unit_of(node.left), self.unit_of(node.right)
                div = isinstance(node.op, ast.Div)
                self.expect(node.left, None if unit is None or right is None else _times(unit, right, -1 if not div
                                                                                         else 1))
                self.expect(node.right, None if unit is None or left is None
                            else (_times(left, unit, -1) if div else _times(unit, left, -1)))
        elif isinstance(node, ast.Call) and isinstance(node.func, ast.Name):
            self.call(node.func.id, node.args, unit)
        elif isinstance(node, ast.Compare):
            sides = [node.left, *node.comparators]
            common = next((u for u in map(self.unit_of, sides) if u is not None), None)
            for side in sides:
                self.expect(side, common)
        elif isinstance(node, ast.BoolOp):
            for part in node.values:
                self.expect(part, None)

    def call(self, name: str, args, unit) -> None:
        if name in _DIMENSIONLESS:
            for arg in args:
                self.expect(arg, {})
        elif name == "sqrt":
            for arg in args:
                self.expect(arg, None if unit is None else _power(unit, Fraction(2)))
        elif name == "where" and len(args) == 3:
            self.expect(args[0], None)
            self._branches(args[1:], unit)
        elif name == "piecewise":
            for condition in args[1::2]:
                self.expect(condition, None)
            self._branches(args[0::2], unit)
        elif name in _SAME:
            self._branches(args, unit)

    def _branches(self, branches, unit) -> None:
        if unit is None:
            unit = next((u for u in map(self.unit_of, branches) if u is not None), None)
        for branch in branches:
            self.expect(branch, unit)


def _number(node) -> Fraction | None:
    if isinstance(node, ast.Constant) and isinstance(node.value, (int, float)) and not isinstance(node.value, bool):
        return Fraction(node.value).limit_denominator(1000)
    if isinstance(node, ast.UnaryOp) and isinstance(node.op, ast.USub):
        inner = _number(node.operand)
        return None if inner is None else -inner
    return None


def field_values(model) -> dict:
    """Key path -> ``(value, unit)`` of every field of ``model`` that validation checks in a unit
    (the ``fields`` of :func:`inferred_units`)."""
    from ..errors import ModelError
    from .paths import get_value
    from .validate import validate_model

    field_units: dict = {}
    validate_model(model, units=field_units)
    out = {}
    for path, unit in field_units.items():
        try:
            out[path] = (get_value(model, path), unit)
        except ModelError:
            continue
    return out


def inferred_units(fields: dict, parameters, *, known: dict | None = None, equal=()) -> dict[str, str]:
    """The unit of every parameter that the fields' expressions fix without contradiction.

    Parameters
    ----------
    fields : dict of str to tuple
        Key path -> ``(value, unit)``: a field's value (a number or an expression) and its unit as
        validation checks it (``"N m"``; a text :func:`parse_unit` cannot read is ignored).
    parameters : collection of str
        The names whose units are sought: the model's parameters, and the signals of ``equal``
        (other names, such as coordinates, are not inferred).
    known : dict of str to str, optional
        Names of known unit (coordinates, speeds, sensors), unit texts.
    equal : sequence of tuple
        ``(name, expression, rate)``: the name has the unit of the expression (a controller's output,
        its saturation), or with ``rate`` true the expression is the name's rate (a controller
        state: the name's unit is the expression's times s).

    Returns
    -------
    dict of str to str
        Name of ``parameters`` -> unit text (:func:`format_unit`), for those whose every use agrees.
    """
    seeds = {}
    for name, text in (known or {}).items():
        unit = parse_unit(text) if isinstance(text, str) else None
        if unit is not None:
            seeds[name] = unit
    trees = []
    for name, text, rate in equal:
        try:
            right = _checked_tree(text).body if isinstance(text, str) else ast.Constant(text)
        except NeedsSymbolic:
            continue
        if rate:
            right = ast.BinOp(right, ast.Mult(), ast.Name("t", ast.Load()))
        trees.append((ast.Compare(ast.Name(name, ast.Load()), [ast.Eq()], [right]), None))
    for value, unit_text in fields.values():
        unit = parse_unit(unit_text) if isinstance(unit_text, str) else None
        if unit is None or not isinstance(value, str):
            continue
        try:
            trees.append((_checked_tree(value).body, unit))
        except NeedsSymbolic:
            continue
    known: dict = dict(seeds)
    refused: set = set()
    while True:   # each pass may fix units that the next pass uses (t1 [s], then T0 in T0*sin(t/t1))
        inference = _Inference(set(parameters) - refused - set(seeds), known)
        for tree, unit in trees:
            inference.expect(tree, unit)
        new = False
        for name, units in inference.found.items():
            texts = {format_unit(u) for u in units}
            if len(texts) > 1 or (name in known and texts != {format_unit(known[name])}):
                refused.add(name)
                new = new or name in known
                known.pop(name, None)
            elif name not in known:
                known[name] = units[0]
                new = True
        if not new:
            return {name: format_unit(unit) for name, unit in sorted(known.items()) if name not in seeds}
