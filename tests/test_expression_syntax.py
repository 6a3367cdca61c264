"""The SymPy-free value of an expression (:func:`flexkane.expression_syntax.simple_value`) agrees with the
SymPy conversion: where it answers, the value is the conversion's (to rounding), and wherever the conversion
refuses an expression or simplifies it, it hands over (raises NeedsSymbolic) instead of answering."""

import math
import random

import pytest
import sympy

from flexkane.errors import ModelError
from flexkane.expression_syntax import NeedsSymbolic, simple_value
from flexkane.expression_values import field_value
from flexkane.expressions import parse_expression, to_float

VALUES = {"x": 0.7, "y": -1.3, "z": 0.0, "L": 2.0, "t": 0.0}


def sympy_value(text, values=VALUES):
    symbols = {name: sympy.Symbol(name, real=True) for name in values}
    expr = parse_expression(text, symbols, path="f")
    return to_float(expr, {symbols[name]: value for name, value in values.items()}, path="f")


def agrees(text, values=VALUES) -> str:
    """'fast' when simple_value answered (and agrees), 'handed over' when it raised NeedsSymbolic."""
    try:
        fast = simple_value(text, values)
    except NeedsSymbolic:
        return "handed over"
    reference = sympy_value(text, values)   # never refuses what the fast path answered
    assert fast == pytest.approx(reference, rel=1e-12, abs=1e-300), text
    return "fast"


@pytest.mark.parametrize("text", [
    "x - x", "1/(t - t)", "(x**60)**2", "*".join(["x"] * 101), "x**60*x**60", "sin(pi)", "1/sin(pi)",
    "exp(200*log(L))", "3**40 + 1 - 3**40 - 1", "0*log(z)", "z/z", "(x + 1)*(1 + x)", "2*(x + y) - 2*x - 2*y",
    "(1e15*x)**100", "sqrt(2)**2 - 2", "x + 1e-20 - x", "where(x + 1e-20 > x, 1, 0)", "log(x - x)",
    " + ".join(f"1/{p}" for p in (999999999999989, 999999999999947, 999999999999883, 999999999999877) * 40),
    "exp(x)*exp(-x) - 1", "abs(-x) - abs(x)", "t*log(t)", "2**t", "x**y", "L**0", "0**-1",
])
def test_what_sympy_simplifies_or_refuses_is_handed_over(text):
    assert agrees(text) == "handed over"


@pytest.mark.parametrize("text", [
    "x*L/2 + 3", "E*b*h**3/12", "mR*(c**2 + d**2)/12", "-pi/2", "where(t < T, Os/T*(t - T/(2*pi)*sin(2*pi*t/T)), Os)",
    "where(t < t1, T0*sin(2*pi*t/t1), 0)", "q0*min(t/T, 1)*(x/L)**(1/7) + gust*sin(2*pi*(x - c_gust*t)/L)",
    "piecewise(1, t < 1, 2, t < 2, 3)", "J1 - m1*(L1/2)**2", "1e-3", "2**10 - 1/3",
])
def test_model_expressions_are_computed_without_sympy(text):
    values = dict.fromkeys(["E", "b", "h", "mR", "c", "d", "T", "Os", "t1", "T0", "q0", "gust", "c_gust", "J1",
                            "m1", "L1"], 1.7) | VALUES
    assert agrees(text, values) == "fast"


def _random_expression(rng: random.Random, depth: int) -> str:
    if depth == 0 or rng.random() < 0.25:
        return rng.choice(["x", "y", "z", "L", "t", "pi", "2", "3", "0.5", "1e-3", "0", "7"])
    kind = rng.random()
    a, b = _random_expression(rng, depth - 1), _random_expression(rng, depth - 1)
    if kind < 0.5:
        return f"({a} {rng.choice(['+', '-', '*', '/'])} {b})"
    if kind < 0.6:
        return f"({a})**{rng.choice(['2', '3', '-1', '0.5', '60', '101'])}"
    if kind < 0.8:
        return f"{rng.choice(['sin', 'cos', 'exp', 'log', 'sqrt', 'abs', 'tanh'])}({a})"
    if kind < 0.9:
        return f"{rng.choice(['min', 'max'])}({a}, {b})"
    return f"where({a} < {b}, {a}, {b})"


def test_random_expressions_agree_or_are_handed_over():
    """Deterministic (seeded): the fast path never answers what SymPy refuses, and agrees where it answers."""
    rng = random.Random(14)
    answered = 0
    for _ in range(600):
        text = _random_expression(rng, 4)
        try:
            fast = simple_value(text, VALUES)
        except NeedsSymbolic:
            continue
        answered += 1
        reference = sympy_value(text)   # a ModelError here would be a refusal the fast path missed
        assert math.isclose(fast, reference, rel_tol=1e-12, abs_tol=1e-300), text
    assert answered > 50


def test_field_value_gives_the_conversions_message():
    with pytest.raises(ModelError) as fast:
        field_value("1/(t - t)", {"t": 0.0}, path="loads.p.torque")
    with pytest.raises(ModelError) as slow:
        sympy_value("1/(t - t)", {"t": 0.0})
    assert fast.value.path == "loads.p.torque"
    assert fast.value.hint == slow.value.hint


@pytest.mark.parametrize("text, unbounded", [
    ("q0*min(t/T, 1)*(x/L)**(1/7) + gust*sin(2*pi*(x - c*t)/L)", False),   # wind-mast: divisions by L only
    ("3*x**2 - exp(x) + abs(x - 1) + where(x < 1, 1, 2)", False),
    (2.5, False),
    ("0.001/(x - 0.35)**2", True),
    ("(x - 0.35)**(-1)", True),
    ("(x - 0.35)**n", True),                 # a power that is not a number may be negative
    ("tan(x)", True),
    ("log(1 + x)", True),
    ("1/t + x", False),                      # singular in t alone: not along the beam
    ("x +* 2", True),                        # outside the syntax: the conversion decides
])
def test_may_be_unbounded_finds_divisions_negative_powers_tan_and_log_of_the_variable(text, unbounded):
    from flexkane.expression_syntax import may_be_unbounded

    assert may_be_unbounded(text, "x") is unbounded
