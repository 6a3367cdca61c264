"""Mutated model files and mutated models give a clean ModelError or a model that derives.

Starting from built-in model files (planar, 3D, and small models of the control and 3D features:
controllers, sensors, drivers, spatial beams and loops), hypothesis drops keys, misspells them or the
names they refer to, renames parts and controller states after result columns, replaces values by wrong
types, negative, huge or non-finite numbers, stray text and random expressions (including attempts
to reach Python objects), and deletes parts that others refer to. Whatever it produces, reading
the file raises :class:`~flexkane.errors.ModelError` or gives a model that ``derive`` accepts (or
refuses with a ModelError); no other exception may escape. The same holds for changes made through
the Python API (:func:`flexkane.model.paths.set_value`).
"""

import copy
import string
import tomllib

import numpy as np
import pytest
import tomli_w
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import flexkane
from flexkane.builtin import builtin_text
from flexkane.errors import ModelError
from flexkane.model.paths import set_value
from model_mutations import COLUMN_NAMES, NAMED_TABLES, feature_texts

BASES = ("pendulum-beam", "falling-beam-exact", "flexible-arm", "four-bar")
#: 3D built-in models, the built-in models with controllers and sensors, and the small models of the 3D and
#: control features (:func:`model_mutations.feature_texts`: controllers, sensors, drivers, spatial beams and
#: loops); the small ones are derived when a mutant is valid.
FEATURES = feature_texts()
FEATURE_BASES = ("robot-arm-3d", "spacecraft-slew", "spacecraft-flexible-slew", "flexible-arm-pid",
                 "flexible-arm-pd", *(f"feature:{name}" for name in FEATURES))
DATA = {name: tomllib.loads(FEATURES[name.removeprefix("feature:")] if name.startswith("feature:")
                            else builtin_text(name)) for name in (*BASES, *FEATURE_BASES)}
#: Most shape functions of a mutated model that is derived (a valid larger one is only validated): the
#: work of a derivation grows steeply with them (40, the limit of a model, takes minutes), and the
#: work of each example is bounded by this cap rather than by a clock.
MAX_DERIVED_SHAPES = 8
SETTINGS = settings(max_examples=80, deadline=None, database=None,
                    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])


def _nodes(node, path=()):
    """Every key path below ``node`` (tables and lists included), as tuples of keys and indices."""
    items = node.items() if isinstance(node, dict) else enumerate(node) if isinstance(node, list) else ()
    for key, child in items:
        yield path + (key,)
        yield from _nodes(child, path + (key,))


PATHS = {name: [p for p in _nodes(data) if p[0] != "sweep"] for name, data in DATA.items()}
PARTS = {name: [p for p in PATHS[name] if len(p) == 2 and p[0] in
                ("bodies", "beams", "joints", "loads", "springs", "constraints", "sensors", "controllers",
                 "distributed_loads")] for name in DATA}

# ------------------------------------------------------------------------------- strategies
_atoms = st.one_of(
    st.integers(-1000, 1000).map(str), st.floats(-1e6, 1e6, allow_nan=False).map(repr),
    st.sampled_from(["t", "x", "xi", "pi", "L", "EI", "g", "mR", "a", "nan", "inf", "True", "None",
                     "__import__", "os", "q1", "u_pivot", "sin", "1e308", "9**9", "'s'", '"text"']))


def _combine(inner):
    return st.one_of(
        st.tuples(inner, st.sampled_from(["+", "-", "*", "/", "**", "//", "%", "<", "==", " and ", "@"]),
                  inner).map("".join),
        st.tuples(st.sampled_from(["sin", "cos", "exp", "log", "sqrt", "abs", "min", "max", "where", "piecewise",
                                   "eval", "open", "getattr", "__import__", "lambda x:", "not "]),
                  st.lists(inner, min_size=0, max_size=3)).map(lambda f: f"{f[0]}({', '.join(f[1])})"),
        st.tuples(inner, st.sampled_from([".__class__", ".real", "[0]", "()", ".mro()"])).map("".join),
        inner.map(lambda e: f"({e})"), inner.map(lambda e: f"-{e}"),
        inner.map(lambda e: f"[{e} for _ in (1,)]"), inner.map(lambda e: f"lambda: {e}"))


EXPRESSIONS = st.recursive(_atoms, _combine, max_leaves=8)

BAD_VALUES = st.one_of(
    st.integers(-10**6, 10**6), st.sampled_from([0, -1, 201, 10**18, -(10**18)]),
    st.floats(allow_nan=True, allow_infinity=True), st.sampled_from([0.0, -1e-300, 1e300, -1e300]),
    st.booleans(), st.text(max_size=12), st.text(string.printable, max_size=30), EXPRESSIONS,
    st.lists(st.one_of(st.integers(-5, 5), st.floats(-10, 10), st.text(max_size=3)), max_size=4),
    st.dictionaries(st.sampled_from(["family", "roots", "x", "coordinate", "speed", "mass_ratio"]),
                    st.one_of(st.integers(-3, 3), st.text(max_size=5), st.lists(st.floats(0.1, 5), max_size=3)),
                    max_size=3),
    st.sampled_from(["clamped-free", "pinned-free", "expression", "axial-fixed-free", "revolute",
                     "prismatic", "weld", "free", "ground", "RB", "B", "rod", "hub", "Q", "radau", "midpoint"]),
)


NUMBERS = st.one_of(st.floats(1e-6, 1e6), st.floats(-1e6, 1e6), st.integers(-5, 300),
                    st.sampled_from([0, 0.0, -0.0, 1e-300, 1e12, 1e300, -1e300, 5e-324]))


def _typo(key: str, draw) -> str:
    kind = draw(st.sampled_from(["drop", "insert", "swap", "case", "underscore"]))
    i = draw(st.integers(0, max(len(key) - 1, 0)))
    if kind == "drop" and len(key) > 1:
        return key[:i] + key[i + 1:]
    if kind == "insert":
        return key[:i] + draw(st.sampled_from("aeiou_x1")) + key[i:]
    if kind == "swap" and len(key) > 1 and i + 1 < len(key):
        return key[:i] + key[i + 1] + key[i] + key[i + 2:]
    if kind == "case":
        return key.swapcase()
    return key + "_"


def _parent(data, path):
    node = data
    for key in path[:-1]:
        node = node[key]
    return node


def _mutate(draw, base: str) -> dict:
    data = copy.deepcopy(DATA[base])
    for _ in range(draw(st.integers(1, 2))):
        op = draw(st.sampled_from(["drop", "rename", "replace", "number", "number", "delete_part", "column",
                                   "typo"]))
        paths = [p for p in _nodes(data) if p[0] != "sweep"]
        named = [p for p in paths if len(p) >= 2 and p[-2] in NAMED_TABLES and isinstance(p[-1], str)]
        if op == "column" and named:   # a part, sensor or controller state named like a result column
            path = draw(st.sampled_from(named))
            parent = _parent(data, path)
            parent[draw(st.sampled_from(COLUMN_NAMES))] = parent.pop(path[-1])
            continue
        references = [p for p in paths if isinstance(_parent(data, p)[p[-1]], str)
                      and _parent(data, p)[p[-1]].isidentifier()]
        listed = [p for p in references if isinstance(p[-1], int)]   # lists of names: dependent speeds, ...
        if op == "typo" and references:   # a misspelt name of a part, a speed, a signal
            path = draw(st.sampled_from(listed if listed and draw(st.booleans()) else references))
            _parent(data, path)[path[-1]] = _typo(_parent(data, path)[path[-1]], draw)
            continue
        if op == "delete_part":
            parts = [p for p in paths if len(p) == 2 and p in PARTS[base]]
            paths = parts or paths
        path = draw(st.sampled_from(paths))
        parent = _parent(data, path)
        key = path[-1]
        if op in ("drop", "delete_part"):
            del parent[key]
        elif op == "rename" and isinstance(key, str):
            parent[_typo(key, draw)] = parent.pop(key)
        elif op == "number":
            parent[key] = draw(NUMBERS)
        else:
            parent[key] = draw(BAD_VALUES)
    return data


def _clean(exc: ModelError) -> None:
    """A ModelError's message names a key path, then what was expected."""
    assert exc.path and str(exc).startswith(f"{exc.path}: expected "), str(exc)


def _shapes(model) -> int:
    """Shape functions of the model's beams (bending in each plane, torsion, axial)."""
    keys = ("n_modes", "n_modes_y", "n_modes_z", "n_torsion", "n_axial")
    return sum(getattr(beam, key, 0) or 0 for beam in model.beams.values() for key in keys)


def _derive_if_valid(model, derive: bool = True) -> None:
    """A valid model derives (when ``derive``), and saving it gives a file that reads back to the same file."""
    try:
        model.validate()
    except ModelError as exc:
        _clean(exc)
        return
    if derive and _shapes(model) <= MAX_DERIVED_SHAPES:
        try:
            flexkane.derive(model)
        except ModelError as exc:
            _clean(exc)
            return
    text = flexkane.dumps_model(flexkane.loads_model(flexkane.dumps_model(model)))
    assert flexkane.dumps_model(flexkane.loads_model(text)) == text


# ------------------------------------------------------------------------------------ tests
@SETTINGS
@given(st.data())
def test_mutated_model_files_give_a_model_error_or_a_model_that_derives(data):
    _mutant_file(data, BASES, derive=lambda base: True)


def _mutant_file(data, bases, derive) -> None:
    """A mutant of one of ``bases`` read back: a clean ModelError or a valid model, derived when
    ``derive(base)``."""
    base = data.draw(st.sampled_from(bases), label="base")
    mutated = _mutate(data.draw, base)
    try:
        text = tomli_w.dumps(mutated)
    except (TypeError, ValueError):   # not representable in TOML (e.g. mixed-type arrays)
        return
    try:
        model = flexkane.loads_model(text, source=base)
    except ModelError as exc:
        _clean(exc)
        return
    _derive_if_valid(model, derive=derive(base))


@SETTINGS
@given(st.data())
def test_values_set_through_the_api_give_a_model_error_or_a_model_that_derives(data):
    base = data.draw(st.sampled_from(BASES), label="base")
    model = flexkane.builtin_model(base)
    for _ in range(data.draw(st.integers(1, 2))):
        path = data.draw(st.sampled_from(PATHS[base]), label="path")
        text = "".join(f"[{k}]" if isinstance(k, int) else f".{k}" for k in path)[1:]
        if data.draw(st.booleans(), label="bare"):
            text = data.draw(st.sampled_from(list(DATA[base].get("parameters", {})) + ["q1", "u_pivot", "zz"]))
        try:
            set_value(model, text, data.draw(st.one_of(BAD_VALUES, NUMBERS), label="value"))
        except ModelError as exc:
            _clean(exc)
            return
    _derive_if_valid(model)


@settings(max_examples=100, deadline=None, database=None)
@given(EXPRESSIONS)
def test_random_expressions_in_value_fields_give_a_model_error_or_a_model_that_derives(expression):
    model = flexkane.builtin_model("pendulum-beam")
    for path in ("beams.rod.EI", "joints.pivot.angle", "initial.q_pivot", "parameters.g"):
        trial = model.copy()
        set_value(trial, path, expression)
        try:
            trial.validate()
        except ModelError as exc:
            _clean(exc)
            continue
        state = flexkane.derive(trial).initial_state(trial)
        assert np.all(np.isfinite(state))


def _feature_test(examples: int, derive: bool):
    """A test of ``examples`` mutants of the 3D and control bases (controllers, sensors, drivers,
    spatial beams and loops); ``derive``: the valid mutants of the small feature models are derived
    (a 3D built-in model takes tens of seconds)."""
    @settings(max_examples=examples, deadline=None, database=None,
              suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
    @given(st.data())
    def test(data):
        _mutant_file(data, FEATURE_BASES, derive=lambda base: derive and base.startswith("feature:"))
    return test


#: A cheap sample, validated only; the slow marker a larger one, derived.
test_mutated_3d_and_control_models_give_a_model_error_or_a_valid_model = _feature_test(100, derive=False)
test_many_mutated_3d_and_control_models_give_a_model_error_or_a_model_that_derives = pytest.mark.slow(
    _feature_test(300, derive=True))
