"""The safe expression language: what it builds, what it refuses, and that it stays fast."""

import json
import math
import resource
import signal
import subprocess
import sys

import pytest
import sympy
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from child_env import child_env

from flexkane.errors import ModelError
from flexkane.expressions import (MAX_DEPTH, MAX_LENGTH, free_names, parse_condition,
                                  parse_expression, resolve_parameters, to_float)

t, T, EI, L, x = sympy.symbols("t T EI L x")
NAMES = {"t": t, "T": T, "EI": EI, "L": L, "x": x}


def parse(text, names=NAMES):
    return parse_expression(text, names, path="loads.push.force[0]")


def refusal(text, names=NAMES) -> ModelError:
    with pytest.raises(ModelError) as info:
        parse(text, names)
    assert info.value.path == "loads.push.force[0]"
    return info.value


# -- what it builds ---------------------------------------------------------------------------
@pytest.mark.parametrize("text, expected", [
    ("sin(2*pi*t/T)", sympy.sin(2 * sympy.pi * t / T)),
    ("EI*L**-2", EI / L**2),
    ("3*EI/L**3", 3 * EI / L**3),
    ("-x + +t - 2", -x + t - 2),
    ("t - x - L", t - x - L),
    ("t / x / L", t / (x * L)),
    ("2**3**2", sympy.Integer(512)),
    ("-2**2", sympy.Integer(-4)),
    ("1/3", sympy.Rational(1, 3)),
    ("0.5*t", sympy.Float(0.5) * t),
    ("exp(-t)*cos(t) + tan(t) + log(x) + sqrt(x) + sinh(t) + cosh(t) + tanh(t)",
     sympy.exp(-t) * sympy.cos(t) + sympy.tan(t) + sympy.log(x) + sympy.sqrt(x)
     + sympy.sinh(t) + sympy.cosh(t) + sympy.tanh(t)),
    ("abs(t - 1)", sympy.Abs(t - 1)),
    ("max(1, 2, 0.5)", sympy.Integer(2)),
    ("min(t, x)", sympy.Min(t, x)),
    ("max(t, 0)", sympy.Max(t, 0)),
    ("  t\t+ 1 ", t + 1),
    ("(t\n + 1)", t + 1),
])
def test_valid_expressions_build_the_sympy_objects_written_by_hand(text, expected):
    assert parse(text) == expected


def test_where_is_a_two_branch_piecewise():
    assert parse("where(t < T, t, 0)") == sympy.Piecewise((t, t < T), (0, True))


def test_where_accepts_chained_comparisons_and_boolean_operators():
    built = parse("where(0 <= t < T and not x > 1 or L >= 2, 1, 2)")
    condition = sympy.Or(sympy.And(0 <= t, t < T, sympy.Not(x > 1)), L >= 2)
    assert built == sympy.Piecewise((1, condition), (2, True))


def test_piecewise_takes_value_condition_pairs_then_a_default():
    built = parse("piecewise(t, t < 1, 2 - t, t < 2, 0)")
    assert built == sympy.Piecewise((t, t < 1), (2 - t, t < 2), (0, True))


def test_a_condition_decided_by_constants_selects_its_branch():
    assert parse("where(1 < 2, t, x)") == t
    assert parse("piecewise(1, 3 < 2, 2, 2 < 3, 3)") == 2


def test_parse_condition_returns_a_sympy_boolean():
    built = parse_condition("t > 1 and x <= 2", NAMES, path="events.stop")
    assert built == sympy.And(t > 1, x <= 2)


def test_numbers_give_sympy_numbers():
    assert parse(3) == sympy.Integer(3) and isinstance(parse(3), sympy.Integer)
    assert parse(0.25) == sympy.Float(0.25) and isinstance(parse(0.25), sympy.Float)


def test_free_names_lists_the_symbols_used():
    assert free_names(parse("EI*sin(t)/L + pi")) == {"EI", "t", "L"}


def test_to_float_evaluates_every_construct():
    expr = parse("where(t < 1, sin(pi*t/2), max(t, 3)) + abs(-x) + sqrt(L)")
    assert to_float(expr, {t: 0.5, x: -2.0, L: 4.0}, path="p") == pytest.approx(
        math.sin(math.pi / 4) + 2 + 2)
    assert to_float(expr, {t: 5.0, x: 0.0, L: 0.0}, path="p") == 5.0


def test_to_float_follows_the_conditions_sympy_rewrites():
    expr = parse("where(0 < where(x < 1, t, 1), 2, 3)")  # SymPy turns the condition into an ITE
    assert to_float(expr, {t: 1.0, x: 0.0}, path="p") == 2.0
    assert to_float(expr, {t: -1.0, x: 0.0}, path="p") == 3.0
    assert to_float(expr, {t: -1.0, x: 5.0}, path="p") == 2.0


@pytest.mark.parametrize("text, values, message", [
    ("t*x", {t: 1.0}, "no value for 'x'"),
    ("1/(t - 1)", {t: 1.0}, "evaluating it failed"),
    ("exp(t)", {t: 1000.0}, "evaluating it failed"),
    ("sqrt(t)", {t: -1.0}, "fractional power"),
])
def test_to_float_reports_missing_values_and_non_finite_results(text, values, message):
    with pytest.raises(ModelError, match=message) as info:
        to_float(parse(text), values, path="loads.push.force[0]")
    assert info.value.path == "loads.push.force[0]"


# -- what it refuses --------------------------------------------------------------------------
@pytest.mark.parametrize("text, message", [
    ("__import__('os').system('true')", "attribute access '.system' is not allowed at column 17"),
    ("().__class__", "attribute access '.__class__' is not allowed at column 3"),
    ("x.real", "attribute access '.real' is not allowed at column 2"),
    ("lambda: 1", "lambda is not allowed at column 1"),
    ("[i for i in range(3)]", "list comprehension is not allowed at column 1"),
    ("{1: 2}", "dict literal is not allowed at column 1"),
    ("'a'", "string literal 'a' is not allowed at column 1"),
    ("f'{t}'", "f-string is not allowed at column 1"),
    ("t if t else 1", "conditional expression 'if ... else' is not allowed at column 1; "
                      "write where(condition, a, b)"),
    ("(x := 1)", "assignment expression ':=' is not allowed at column 2"),
    ("sin(x=1)", "keyword argument 'x=' is not allowed at column 5"),
    ("sin(**t)", "keyword argument unpacking '**' is not allowed at column 5"),
    ("sin(*t)", "starred argument '*' is not allowed at column 5"),
    ("t[0]", "subscript '[...]' is not allowed at column 1"),
    ("1j", "complex number 1j is not allowed"),
    ("True", "constant True is not allowed"),
    ("t % 2", "operator '%' is not allowed at column 3"),
    ("t ^ 2", "operator '^' is not allowed at column 3; write ** for a power"),
    ("~t", "operator '~' is not allowed"),
    ("t < 1", "condition 't < 1' where a value is expected"),
    ("where(t, 1, 2)", "value 't' where a condition is expected at column 7"),
    ("where(t == 1, 1, 2)", "comparison '==' is not allowed at column 9"),
    ("where(t < 1, 1)", "where() with 2 arguments"),
    ("piecewise(1, t < 1, 2, 3)", "piecewise() with 4 arguments"),
    ("sin(1, 2)", "sin() with 2 arguments"),
    ("max(t)", "max() with 1 argument"),
    ("sin", "function 'sin' without arguments"),
    ("T(2)", "call of 'T', which is not a function"),
    ("sine(t)", "unknown function 'sine' at column 1; did you mean 'sin'?"),
    ("eval('1')", "unknown function 'eval' at column 1"),
    ("3*Ei", "unknown name 'Ei' at column 3; did you mean 'EI'?"),
    ("3*ei", "did you mean 'EI'?"),
    ("qqq", "unknown name 'qqq' at column 1; allowed names: EI, L, T, pi, t, x"),
    ("1 +* 2", "syntax error at column 4"),
    ("sin(t", "syntax error"),
    ("", "the text is empty"),
])
def test_refusals_name_the_offending_token_and_its_column(text, message):
    assert message in str(refusal(text))


def test_columns_of_a_multi_line_expression_give_the_line():
    assert "line 2, column 4" in str(refusal("(t +\n  x.real)"))


def test_columns_count_characters_not_bytes():
    names = {"é": sympy.Symbol("é"), "t": t}
    assert "unknown name 'b' at column 5" in str(refusal("é + b", names))


#: Texts that would make huge numbers if computed, and what the refusal says (None: accepted).
HUGE_NUMBER_CASES = [
    ("9**9**9", "exponent 9**9 above 100"),
    ("2**1000", "exponent 1000 above 100"),
    ("t**-101", "exponent -101 above 100"),
    ("(3*t)**where(t < 1, 1000, 2)", "exponent where(t < 1, 1000, 2) above 100"),
    ("10**16", None),
    ("10000000000000000", "integer 10000000000000000 above 1e+15"),
    ("1e400", "beyond the floating-point range"),
    ("1e300*1e300", "beyond the floating-point range"),
    ("exp(1000)", "exp() overflows"),
    ("1/0", "division by zero"),
    ("t/(x - x)", "division by zero"),
    ("0**-1", "divides by zero"),
    ("sqrt(-1)", "sqrt() is not defined"),
    ("log(0)", "log() is not defined"),
    ("(-8)**(1/3)", "not a real number"),
    ("tan(pi/2)", "undefined or infinite"),
    ("((3*t)**100)**100", "a power of a number with too many digits"),
    ("exp(1000000000000000*log(3*t))", "exp() of a logarithm times a number above 100"),
]

#: CPU seconds allowed to the child that parses every text of HUGE_NUMBER_CASES, imports included.
#: The child needs about 2 CPU seconds; computing a single one of the refused numbers (9**9**9 has
#: 370 million digits) would take far longer than this, whatever the load of the machine.
_LIMIT_CPU_SECONDS = 30

_LIMIT_CHILD = """
import json, sys, sympy
from flexkane.errors import ModelError
from flexkane.expressions import parse_expression
names = {name: sympy.Symbol(name) for name in ("t", "T", "EI", "L", "x")}
for text in json.loads(sys.argv[1]):
    sys.stderr.write(repr(text) + "\\n")
    sys.stderr.flush()
    try:
        outcome = repr(parse_expression(text, names, path="loads.push.force[0]"))
    except ModelError as exc:
        outcome = str(exc)
    print(json.dumps([text, outcome]), flush=True)
"""


@pytest.fixture(scope="module")
def huge_number_outcomes() -> dict[str, str]:
    """What parsing each text of HUGE_NUMBER_CASES gives, in a child process whose CPU time is
    limited (bounded work without a clock: past the limit, SIGXCPU ends the child)."""
    def limit():
        resource.setrlimit(resource.RLIMIT_CPU, (_LIMIT_CPU_SECONDS, _LIMIT_CPU_SECONDS + 5))
    child = subprocess.run([sys.executable, "-c", _LIMIT_CHILD, json.dumps([text for text, _ in HUGE_NUMBER_CASES])],
                           capture_output=True, text=True, env=child_env(), preexec_fn=limit)
    ended = signal.Signals(-child.returncode).name if child.returncode < 0 else child.returncode
    assert child.returncode == 0, f"the parsing child ended with {ended} while parsing {child.stderr[-500:]}"
    return dict(json.loads(line) for line in child.stdout.splitlines())


@pytest.mark.parametrize("text, message", HUGE_NUMBER_CASES)
def test_limits_refuse_huge_numbers_before_they_are_computed(text, message, huge_number_outcomes):
    if message is None:
        assert parse(text) == 10**16 and huge_number_outcomes[text] == "10000000000000000"
    else:
        assert message in str(refusal(text)) and message in huge_number_outcomes[text]


def test_too_long_text_is_refused():
    error = refusal("t+" * (MAX_LENGTH // 2) + "1")
    assert f"at most {MAX_LENGTH} characters" in str(error)
    assert len(str(error)) < 400


def test_too_deep_nesting_is_refused():
    assert f"nesting deeper than {MAX_DEPTH} levels" in str(refusal("sin(" * 60 + "t" + ")" * 60))
    assert "nesting deeper" in str(refusal("-" * 60 + "t"))
    assert "syntax error" in str(refusal("(" * 300 + "t" + ")" * 300))


def test_too_many_elements_are_refused():
    assert "more than 500 elements" in str(refusal("+".join(f"t*{k}" for k in range(300))))


def test_a_long_flat_sum_is_not_deep():
    assert parse("+".join(["t"] * 200)) == 200 * t


@pytest.mark.parametrize("value, message", [
    (True, "true and false are not numbers"),
    (math.nan, "a finite number"),
    (math.inf, "a finite number"),
    (-math.inf, "a finite number"),
    (None, "a number or an expression"),
    ([1], "a number or an expression"),
    (10**16, "write large numbers in floating point"),
])
def test_bad_values_of_other_types_are_refused(value, message):
    assert message in str(refusal(value))


# -- parameters -------------------------------------------------------------------------------
def test_parameters_refer_to_each_other_in_any_order():
    values = resolve_parameters({"Iz": "mR*(c**2 + d**2)/12", "mR": 3, "c": "d/2", "d": 0.2})
    assert list(values) == ["Iz", "mR", "c", "d"]
    assert values["Iz"] == pytest.approx(3 * (0.1**2 + 0.2**2) / 12)
    assert all(isinstance(value, float) for value in values.values())


def test_parameter_cycles_are_named():
    with pytest.raises(ModelError, match=r"cycle: a -> b -> c -> a") as info:
        resolve_parameters({"a": "b + 1", "b": "2*c", "c": "a", "d": 1})
    assert info.value.path == "parameters.a"
    with pytest.raises(ModelError, match=r"cycle: a -> a"):
        resolve_parameters({"a": "a"})


@pytest.mark.parametrize("definitions, path, message", [
    ({"a": "sin(t)"}, "parameters.a", "cannot depend on time"),
    ({"a": "b"}, "parameters.a", "unknown name 'b'"),
    ({"t": 1.0}, "parameters.t", "'t' is time"),
    ({"pi": 3.0}, "parameters.pi", "not reserved"),
    ({"sin": 3.0}, "parameters.sin", "not reserved"),
    ({"2a": 3.0}, "parameters.2a", "ASCII letters"),
    ({"a": "1/(b - 1)", "b": 1}, "parameters.a", "finite real value"),
    ({"a": "sqrt(b)", "b": -1}, "parameters.a", "finite real value"),
    ({"a": "exp(b)", "b": 1000}, "parameters.a", "finite real value"),
])
def test_bad_parameters_are_reported_with_their_path(definitions, path, message):
    with pytest.raises(ModelError, match=message) as info:
        resolve_parameters(definitions)
    assert info.value.path == path


# -- properties -------------------------------------------------------------------------------
VALID = ["sin(2*pi*t/T)", "EI*L**-2 + 3", "where(t < T, t**2, 0)", "max(t, x, 1)",
         "piecewise(t, t < 1, 2 - t, t < 2 and x > 0, 0)", "exp(-t/T)*cos(2*pi*t)",
         "sqrt(abs(x))*log(1 + t**2)", "(t - 1)**3/(x + 2)", "-(t*EI)/(L**3) + 0.5e-3"]
PIECES = ["t", "x", "EI", "pi", "2", "9", "1e300", "100", "**", "*", "/", "+", "-", "(", ")",
          ",", "<", " and ", " not ", ".", "[", "]", "'", "sin(", "exp(", "log(", "where(",
          "max(", "lambda:", "__class__", " if ", ":=", "=", "{", "}", "@", "%", "j", "9**9**9"]


#: Most Python function calls one parse may make. The longest accepted texts (a sum of 120 terms,
#: 49 nested sines, (t + 1)**100) take about 130,000; an unbounded expansion or simplification
#: takes many millions. Counted calls, unlike seconds, do not depend on the machine or its load.
MAX_CALLS = 2_000_000


def counted_calls(function, *args):
    """``function(*args)`` and the number of Python and built-in function calls it made."""
    calls = 0

    def count(frame, event, arg):
        nonlocal calls
        if event in ("call", "c_call"):
            calls += 1
    sys.setprofile(count)
    try:
        return function(*args), calls
    finally:
        sys.setprofile(None)


def check_parse_outcome(text):
    (result, calls) = counted_calls(_outcome, text)
    assert result is None or isinstance(result, sympy.Expr)
    assert calls < MAX_CALLS, f"{calls} function calls to parse {text!r}"


def _outcome(text):
    try:
        return parse(text)
    except ModelError:
        return None


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.text(max_size=80))
def test_random_text_gives_an_expression_or_a_model_error(text):
    check_parse_outcome(text)


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.text(alphabet="tx0123456789.e+-*/()<>=,abcdEIpiLn ", max_size=60))
def test_random_arithmetic_like_text_gives_an_expression_or_a_model_error(text):
    check_parse_outcome(text)


@st.composite
def mutated_expressions(draw):
    text = draw(st.sampled_from(VALID))
    for _ in range(draw(st.integers(1, 4))):
        position = draw(st.integers(0, len(text)))
        kind = draw(st.sampled_from(["insert", "delete", "replace", "duplicate"]))
        if kind == "insert":
            text = text[:position] + draw(st.sampled_from(PIECES)) + text[position:]
        elif kind == "delete":
            text = text[:position] + text[position + draw(st.integers(1, 3)):]
        elif kind == "replace":
            text = text[:position] + draw(st.sampled_from(PIECES)) + text[position + 1:]
        else:
            stop = draw(st.integers(position, len(text)))
            text = text[:stop] + text[position:stop] + text[stop:]
    return text


@settings(max_examples=400, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(mutated_expressions())
def test_mutated_valid_expressions_give_an_expression_or_a_model_error(text):
    check_parse_outcome(text)
