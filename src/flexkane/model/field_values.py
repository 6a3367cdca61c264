"""The numbers of a model's fields: the one evaluator of field values.

Every field of a model (a mass, a length, a beam's rigidity, an outline point, an initial value, a
load at some time) is a number or an expression of the model's parameters (and, where the field
allows, of ``t``). :class:`FieldValues` resolves the parameters once and evaluates any field from
them; validation, the derivation's constants and initial state, the linearization's operating point,
the animation's outlines and the validity checks all use it, so a field has one value and one error
message wherever it is read.

The value is computed by :func:`flexkane.expression_values.field_value`: straight from the syntax
tree in floating point where that gives the SymPy conversion's answer, else through
:func:`flexkane.expressions.parse_expression` and :func:`flexkane.expressions.to_float` (the same
value and the same messages, which name the field's key path).
"""

from __future__ import annotations

from collections.abc import Mapping

from ..errors import ModelError
from ..expression_syntax import NeedsSymbolic, check_parameter_name, dependency_order, simple_names, simple_value
from ..expression_values import field_value

__all__ = ["FieldValues", "parameter_values"]


def parameter_values(definitions: Mapping[str, object], *, path_prefix: str = "parameters") -> dict[str, float]:
    """The value of every parameter, in the order of ``definitions``.

    Without SymPy when every definition is simple (:func:`~flexkane.expression_syntax.simple_value`),
    else by :func:`~flexkane.expressions.resolve_parameters`, which also gives every message.

    Parameters
    ----------
    definitions : Mapping[str, int | float | str]
        Parameter name -> number or expression of other parameters and ``pi``.
    path_prefix : str
        Key path of the table, for error messages.

    Returns
    -------
    dict of str to float
        The values [each parameter's unit].

    Raises
    ------
    ModelError
        For an invalid name or expression, an unknown name, or a circular definition.
    """
    def path_of(name: str) -> str:
        return f"{path_prefix}.{name}" if path_prefix else name

    try:
        if not isinstance(definitions, dict):
            raise NeedsSymbolic
        for name in definitions:
            check_parameter_name(name, path_of(name))
        position = {name: k for k, name in enumerate(definitions)}
        dependencies = {name: sorted(simple_names(value, definitions), key=position.__getitem__)
                        for name, value in definitions.items()}
        values: dict[str, float] = {}
        for name in dependency_order(dependencies, definitions, path_of):
            values[name] = simple_value(definitions[name], values)
        return {name: values[name] for name in definitions}
    except (NeedsSymbolic, ModelError):
        from ..expressions import resolve_parameters

        return resolve_parameters(definitions, path_prefix=path_prefix)


class FieldValues:
    """Numeric values of a model's fields, from its parameters.

    Parameters
    ----------
    model : Model
        The model whose ``parameters`` the fields may use (only its parameters are read, once).

    Attributes
    ----------
    parameters : dict of str to float
        The value of every parameter by name [its unit].

    Examples
    --------
    >>> fields = FieldValues(model)                                     # doctest: +SKIP
    >>> fields.value(model.beams["arm"].L, "beams.arm.L")                # doctest: +SKIP
    >>> fields.value(model.joints["hub"].torque, "joints.hub.torque", t=0.5)  # doctest: +SKIP
    """

    def __init__(self, model):
        self.parameters = parameter_values(model.parameters)

    def value(self, text, path: str, *, what: str | None = None, **names: float) -> float:
        """The value of one field [its unit].

        Parameters
        ----------
        text : int, float or str
            The field as given: a number or an expression of the parameters and ``names``.
        path : str
            Its key path (``beams.arm.EI``), named by any error.
        what : str, optional
            What the field is, with its unit (``"length [m]"``); when given, an error says it.
        **names : float
            Values of further names the field may use (``t`` [s] for a time law, ``x`` [m]).

        Raises
        ------
        ModelError
            If the text is not an expression of known names, or its value is not finite and real.
        """
        return field_value(text, {**self.parameters, **names}, path=path, what=what)

    def value_or(self, texts: Mapping[str, object], name: str, prefix: str, default: float = 0.0) -> float:
        """The value of the field ``texts[name]`` (key path ``prefix.name``), ``default`` if there is none.

        Parameters
        ----------
        texts : Mapping[str, int | float | str]
            A table of fields by name, e.g. the model's ``initial``.
        name : str
            The entry.
        prefix : str
            Key path of the table (``initial``).
        default : float
            The value of a missing entry [its unit].
        """
        if name not in texts:
            return float(default)
        return self.value(texts[name], f"{prefix}.{name}")
