"""One evaluator of a model's field values (``flexkane.model.field_values``), used by every stage."""

import ast
import math
import pathlib

import pytest
import sympy as sp

from flexkane.errors import ModelError
from flexkane.expressions import parse_expression, to_float
from flexkane.model import Model
from flexkane.model.field_values import FieldValues, parameter_values

SRC = pathlib.Path(__file__).resolve().parents[2] / "src" / "flexkane"


def model_with(parameters) -> Model:
    return Model(parameters=dict(parameters))


def test_values_are_those_of_the_symbolic_conversion():
    definitions = {"a": 2, "b": "3*a + sin(a)", "c": "b**2/where(a > 1, a, 1)"}
    fields = FieldValues(model_with(definitions))
    symbols = {name: sp.Symbol(name, real=True) for name in [*definitions, "t"]}
    numbers = {symbols["a"]: 2.0, symbols["b"]: 6 + math.sin(2.0)}
    numbers[symbols["c"]] = numbers[symbols["b"]] ** 2 / 2
    assert fields.parameters == pytest.approx({"a": 2.0, "b": 6 + math.sin(2.0), "c": numbers[symbols["c"]]},
                                              rel=1e-15)
    for text in ("c - a*t", "exp(-t)*cos(b*t)", "sqrt(a)*sqrt(a) + t"):   # the last one SymPy simplifies
        expected = to_float(parse_expression(text, symbols, path="x"), {**numbers, symbols["t"]: 0.3}, path="x")
        assert fields.value(text, "loads.L.torque", t=0.3) == pytest.approx(expected, rel=1e-15)


def test_a_missing_entry_takes_the_default_and_a_given_one_its_value():
    fields = FieldValues(model_with({"w": 4.0}))
    initial = {"q1": "w/2"}
    assert fields.value_or(initial, "q1", "initial") == 2.0
    assert fields.value_or(initial, "u1", "initial") == 0.0


def test_an_error_names_the_key_path_and_what_was_expected():
    fields = FieldValues(model_with({"m": 1.0}))
    with pytest.raises(ModelError) as info:
        fields.value("m + q", "beams.arm.L", what="length [m]")
    assert info.value.path == "beams.arm.L" and "length [m]" in info.value.expected
    assert "q" in (info.value.hint or "")
    with pytest.raises(ModelError) as info:
        fields.value("1/(t - 2)", "joints.hub.torque", what="torque [N m]", t=2.0)
    assert info.value.path == "joints.hub.torque" and "at t = 2" in info.value.expected


def test_parameter_errors_name_the_parameter():
    with pytest.raises(ModelError) as info:
        parameter_values({"a": "b", "b": "a"})
    assert info.value.path.startswith("parameters.")


def calls(tree: ast.AST, name: str) -> int:
    return sum(1 for node in ast.walk(tree) if isinstance(node, ast.Call)
               and getattr(node.func, "id", getattr(node.func, "attr", None)) == name)


def test_fields_are_evaluated_in_one_place():
    """Only the evaluator resolves a model's parameters or turns a field's text into a number."""
    owners = {"expressions.py", "expression_syntax.py", "expression_values.py", "model/field_values.py"}
    offenders = []
    for path in sorted(SRC.rglob("*.py")):
        relative = path.relative_to(SRC).as_posix()
        if relative in owners:
            continue
        tree = ast.parse(path.read_text(encoding="utf-8"))
        for name in ("resolve_parameters", "simple_value"):
            if calls(tree, name):
                offenders.append(f"{relative} calls {name}")
        for node in ast.walk(tree):   # to_float(parse_expression(text ...)): a private evaluator
            if isinstance(node, ast.Call) and getattr(node.func, "id", None) == "to_float" and node.args \
                    and isinstance(node.args[0], ast.Call) \
                    and getattr(node.args[0].func, "id", None) == "parse_expression":
                offenders.append(f"{relative}:{node.lineno} evaluates a field itself")
    assert not offenders, offenders
