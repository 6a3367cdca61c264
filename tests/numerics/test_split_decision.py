"""When a large right-hand side is split into term tables and parts (flexkane.numerics.codegen): only when
it has long sums to tabulate. A long chain's many short statements stay one function, whose values
equal those of the split form."""

from __future__ import annotations

import re
import sys
from pathlib import Path

import numpy as np
import pytest

import flexkane
from flexkane.numerics import codegen, large_rhs
from flexkane.numerics.codegen import generate_rhs_source
from flexkane.numerics.jit_module import compose_module_source

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "benchmarks"))
from scaling import chain_model  # noqa: E402


def _python_rhs(source: str):
    """The generated ``rhs`` run by Python (decorators removed): no compile, the same arithmetic."""
    text = re.sub(r"^@njit\(.*\)$", "", compose_module_source(source, "test"), flags=re.M)
    namespace: dict = {}
    exec(compile(text, "<generated>", "exec"), namespace)   # our own generated code, not user text
    return namespace["rhs"]


@pytest.fixture(scope="module")
def equations():
    return {"chain_model(3)": flexkane.derive(chain_model(3), cache=False),
            "four-bar": flexkane.derive(flexkane.builtin_model("four-bar"), cache=False)}


@pytest.mark.parametrize("label", ["chain_model(3)", "four-bar"])
def test_short_statements_stay_one_function_and_equal_the_split_form(equations, label, monkeypatch):
    eom = equations[label]
    monkeypatch.setattr(large_rhs, "SPLIT_CHARS", 200)      # far above the split size
    straight = generate_rhs_source(eom)
    assert "_part0" not in straight and "table_sums" not in straight
    monkeypatch.setattr(codegen, "_has_long_sums", lambda exprs: True)
    split = generate_rhs_source(eom)
    assert "def rhs_part1(" in split
    rhs_straight, rhs_split = _python_rhs(straight), _python_rhs(split)
    rng = np.random.default_rng(11)
    n, p = len(eom.q) + len(eom.u), eom.parameter_vector()
    for _ in range(10):
        t, y = float(rng.uniform(0.0, 1.0)), rng.normal(scale=0.5, size=n)
        a, b = np.empty(n), np.empty(n)
        assert rhs_straight(t, y, p, a) == rhs_split(t, y, p, b) == 0
        # the same sums in another order, through a solve with stiff modal rows (accelerations of
        # 5e5 beside 0.1): round-off, not a 1e-12 agreement
        np.testing.assert_allclose(a, b, rtol=1e-10, atol=1e-11 * np.max(np.abs(b)))


def test_a_model_with_long_sums_is_still_split(monkeypatch):
    eom = flexkane.derive(flexkane.builtin_model("falling-beam-exact").with_modes(12), cache=False)
    monkeypatch.setattr(large_rhs, "SPLIT_CHARS", 200)
    source = generate_rhs_source(eom)
    assert "rhs_table_sums(w, p, " in source and "def rhs_part0(" in source
