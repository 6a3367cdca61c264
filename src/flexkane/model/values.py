"""Field values as symbols: one derivation serves every numeric value.

Every physical field of a model becomes a SymPy expression for the derivation:

* a literal zero stays ``0`` (zeros are part of the model's structure: they simplify the equations);
* a field that names a parameter becomes that parameter's symbol (the chapter's ``mR``, ``Iz``, ``b``);
* any other value becomes a symbol of its own named after the field (``m_RB``, ``L_arm``), whose
  numeric value is computed from the field's text at run time;
* fields that may depend on time (loads, drivers) are parsed into expressions of ``t`` and the
  parameter symbols.

:class:`FieldSymbols` records, for each symbol, the key path of the field that gives its value; the
numbers come from the model's one evaluator (:class:`flexkane.model.field_values.FieldValues`, used by
:func:`flexkane.kane.numeric.constant_values`).
"""

from __future__ import annotations

import re

import sympy as sp

from .model import Model

__all__ = ["FieldSymbols", "GeneratedSymbol", "TIME", "symbol_order"]

#: The time symbol t [s].
TIME = sp.Symbol("t", real=True)
_SAFE = re.compile(r"[^0-9A-Za-z_]")


class GeneratedSymbol(sp.Symbol):
    """A symbol flexkane makes: a field value, a modal constant, a coordinate, a speed.

    Generated symbols and the symbols of a user's parameters live in separate namespaces: a
    ``GeneratedSymbol("H_11")`` never equals (nor hashes like) the parameter symbol
    ``Symbol("H_11")``, even though both print alike. A parameter's name therefore never changes
    what a generated constant stands for (model validation also refuses such names, so that printed
    equations stay readable).
    """

    @classmethod
    def class_key(cls):
        """Sort like a plain symbol: printed equations keep the order of their terms."""
        return sp.Symbol.class_key()


# SymPy orders the terms of sums and products by class name (``Basic.compare``): under the name of a
# plain symbol, generated symbols keep the canonical order, printed equations and generated code
# they always had. Equality and hashing see the class itself, and pickling its qualified name.
GeneratedSymbol.__name__ = "Symbol"


def symbol_order(symbol: sp.Symbol) -> tuple[str, bool]:
    """Sort key of symbols: by name in natural order (E_1, E_2, ..., E_10), a parameter before a
    generated symbol printed alike."""
    from ..natural_order import natural_key

    return (natural_key(symbol.name), isinstance(symbol, GeneratedSymbol))


class FieldSymbols:
    """Symbols for a model's parameters and field values.

    Parameters
    ----------
    model : Model
        The (validated) model.
    """

    def __init__(self, model: Model):
        from ..expressions import parse_expression

        self._parse = parse_expression
        self.model = model
        self.parameters = {name: sp.Symbol(name, real=True) for name in model.parameters}
        #: symbol -> (path, value text or number) for field symbols
        self.definitions: dict[sp.Symbol, tuple[str, object]] = {}
        self._by_path: dict[str, sp.Expr] = {}
        #: names efforts may use besides t and the parameters (coordinates, speeds, sensors,
        #: controller states and outputs) -> their expressions (set by flexkane.kane.controllers)
        self.signals: dict[str, sp.Expr] = {}

    # ------------------------------------------------------------------ construction
    def _fresh_name(self, base: str) -> str:
        base = _SAFE.sub("_", base)
        taken = set(self.model.parameters) | {s.name for s in self.definitions} | {"t", "pi"}
        name, k = base, 1
        while name in taken:
            k += 1
            name = f"{base}{k}"
        return name

    def value(self, path: str, value, name: str) -> sp.Expr:
        """The expression standing for a constant field.

        Parameters
        ----------
        path : str
            Key path of the field (for messages and for ``--set``).
        value : int, float or str
            The field as given.
        name : str
            Preferred symbol name when the field needs a symbol of its own.
        """
        if path in self._by_path:
            return self._by_path[path]
        if isinstance(value, (int, float)) and not isinstance(value, bool) and value == 0:
            expr = sp.Integer(0)
        elif isinstance(value, str) and value.strip() in self.parameters:
            expr = self.parameters[value.strip()]
        else:
            # check now that it parses and uses only parameters
            self._parse(value, {**self.parameters}, path=path)
            symbol = GeneratedSymbol(self._fresh_name(name), real=True)
            self.definitions[symbol] = (path, value)
            expr = symbol
        self._by_path[path] = expr
        return expr

    def effort(self, path: str, value) -> sp.Expr:
        """An effort (torque, force, rest position, controller rate or output): an expression of t,
        the parameters and the :attr:`signals` (state feedback), kept as it is in the equations."""
        names = {**self.parameters, **self.signals, "t": TIME}
        return self._parse(value, names, path=path)

    def time_function(self, path: str, value) -> sp.Expr:
        """An expression of t and the parameters (loads, drivers); kept as it is in the equations."""
        names = {**self.parameters, "t": TIME}
        return self._parse(value, names, path=path)
