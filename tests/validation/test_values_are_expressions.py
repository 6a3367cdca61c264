"""Every value of a model file is a number or an expression of the parameters (issue 14, item 6)."""

import pytest

import flexkane
from flexkane.derivation_cache import structure_signature


def test_loop_stabilization_rate_accepts_an_expression_of_the_parameters():
    model = flexkane.builtin_model("four-bar")
    model.parameters["beta0"] = 4.0
    model.constraints["loop"].stabilization = "2*beta0"
    model.validate()
    eom = flexkane.derive(model)
    values = {s.name: v for s, v in eom.constant_values(model).items()}
    assert values["beta_loop"] == 8.0
    other = model.copy()
    other.parameters["beta0"] = 5.0
    assert structure_signature(other) == structure_signature(model)
    assert {s.name: v for s, v in eom.constant_values(other).items()}["beta_loop"] == 10.0
    model.parameters["beta0"] = -1.0
    with pytest.raises(flexkane.errors.ModelError, match=r"constraints\.loop\.stabilization.*non-negative"):
        model.validate()
