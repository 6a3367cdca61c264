"""User names never collide with the names flexkane generates (modal constants, beam masses,
field values, coordinates).

Every parameter of a built-in model is renamed to each generated name of that model (with every
reference to it in the model's expressions); the model must then either be refused with a
ModelError naming both the parameter and the generated name, or give exactly the same equations
of motion numerically. Separately, the symbols of parameters and generated constants are distinct
objects even when printed alike, so a bypass of the refusal cannot change a result either."""

import re

import numpy as np
import pytest
import sympy as sp
import tomli_w

import flexkane
from flexkane.errors import ModelError
from flexkane.kane.equations import derive
from flexkane.model import validate
from flexkane.model.toml_io import _plain, loads_model, model_to_dict
from flexkane.model.values import GeneratedSymbol

_IDENTIFIER = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")
_DERIVED: dict = {}


def _derived(name: str):
    if name not in _DERIVED:
        model = flexkane.builtin_model(name)
        _DERIVED[name] = (model, derive(model))
    return _DERIVED[name]


def generated_names(eom) -> list[str]:
    """Identifier names of every symbol the derivation generated (constants and coordinates)."""
    symbols = [s for s in [*eom.constants, *eom.chain.q, *eom.chain.u] if isinstance(s, GeneratedSymbol)]
    return sorted({s.name for s in symbols if _IDENTIFIER.fullmatch(s.name)})


def _renamed(data, old: str, new: str):
    """The model's data with parameter ``old`` renamed ``new``, in every expression too."""
    if isinstance(data, dict):
        return {key: _renamed(value, old, new) for key, value in data.items()}
    if isinstance(data, list):
        return [_renamed(value, old, new) for value in data]
    if isinstance(data, str):
        return _IDENTIFIER.sub(lambda m: new if m.group(0) == old else m.group(0), data)
    return data


def _numbers(eom) -> np.ndarray:
    """Mass matrix and forcing at a fixed state (coordinates, speeds, controller states) and time, as floats."""
    values = {s: sp.Float(v) for s, v in eom.constant_values().items()}
    state = {s: sp.Float(0.1 + 0.01 * k) for k, s in enumerate([*eom.q, *eom.u, *eom.z])}   # z: controller states
    point = {**values, **state, eom.t: sp.Float(0.3)}
    exprs = [*eom.mass_matrix, *eom.forcing]
    return np.array([float(e.xreplace(point).evalf()) for e in exprs])


def _check_renames(example: str, names: list[str] | None = None) -> int:
    model, eom = _derived(example)
    reference = _numbers(eom)
    data = _plain(model_to_dict(model))
    refused = 0
    for parameter in model.parameters:
        for name in names or generated_names(eom):
            if name == parameter:
                continue
            renamed = dict(_renamed(data, parameter, name))
            renamed["parameters"] = {(name if k == parameter else k): v
                                     for k, v in _renamed(data["parameters"], parameter, name).items()}
            try:
                other = derive(loads_model(tomli_w.dumps(renamed)))
            except ModelError as exc:
                assert name in str(exc), (parameter, name, str(exc))
                refused += 1
                continue
            # the same equations up to the order of SymPy's sums and products, which follows the
            # symbols' names: round-off only (a collision with a generated symbol changes the physics)
            np.testing.assert_allclose(_numbers(other), reference, rtol=1e-12, atol=1e-12 * np.abs(reference).max(),
                                       err_msg=f"{example}: {parameter} renamed {name}")
    return refused


def test_renaming_parameters_of_flexible_arm_to_generated_names_is_refused_or_harmless():
    _, eom = _derived("flexible-arm")
    names = generated_names(eom)
    assert {"H_11", "m_link", "G_12", "E_1", "q_shoulder"} <= set(names)
    picked = ["H_11", "m_link", "G_12", "E_3", "q_link_1", "u_shoulder"]
    assert _check_renames("flexible-arm", picked) > 0


def test_a_modal_constant_name_is_refused_naming_both():
    model = flexkane.builtin_model("flexible-arm")
    data = _plain(model_to_dict(model))
    data["parameters"]["H_11"] = data["parameters"].pop("EI")
    data["beams"]["link"]["EI"] = "H_11"
    with pytest.raises(ModelError) as info:
        loads_model(tomli_w.dumps(data))
    assert info.value.path == "parameters.H_11"
    assert "modal constant H_11" in str(info.value) and "beam 'link'" in str(info.value)


def test_parameter_and_generated_symbols_are_distinct_even_when_the_refusal_is_bypassed(monkeypatch):
    assert GeneratedSymbol("H_11", real=True) != sp.Symbol("H_11", real=True)
    model, eom = _derived("flexible-arm")
    data = _plain(model_to_dict(model))
    data["parameters"]["H_11"] = data["parameters"].pop("EI")
    data["beams"]["link"]["EI"] = "H_11"
    data["parameters"]["m_link"] = 123.0   # an unused parameter named like the beam's mass
    monkeypatch.setattr(validate, "_check_parameter_names", lambda model: None)
    other = derive(loads_model(tomli_w.dumps(data)))
    values = other.constant_values()
    by_kind = {(isinstance(s, GeneratedSymbol), s.name): v for s, v in values.items()
               if s.name in ("H_11", "m_link")}
    assert by_kind[(False, "H_11")] == 12.0 and by_kind[(False, "m_link")] == 123.0
    assert by_kind[(True, "H_11")] != 12.0
    assert np.array_equal(_numbers(other), _numbers(eom))


@pytest.mark.slow
@pytest.mark.parametrize("example", flexkane.builtin_names())
def test_renaming_every_parameter_of_every_example_to_every_generated_name(example):
    _check_renames(example)
