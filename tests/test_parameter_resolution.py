"""Parameter resolution is linear in the number of parameters: each definition is parsed once,
its free names are computed once and it is evaluated once, in a topological order; a cycle is
reported with the cycle named."""

import pytest

from flexkane import expressions
from flexkane.errors import ModelError


def _chain(n: int) -> dict:
    """``p0 = 1``, ``p_k = p_(k-1) + 1``, written in reverse order (the worst case for a scan)."""
    definitions = {f"p{k}": f"p{k - 1} + 1" for k in range(n - 1, 0, -1)}
    definitions["p0"] = 1.0
    return definitions


def _count_work(monkeypatch) -> dict:
    counts = {"free_names": 0, "to_float": 0}
    for name in counts:
        original = getattr(expressions, name)

        def counted(*args, _original=original, _name=name, **kwargs):
            counts[_name] += 1
            return _original(*args, **kwargs)

        monkeypatch.setattr(expressions, name, counted)
    return counts


def _resolve_and_count(monkeypatch, n: int) -> None:
    counts = _count_work(monkeypatch)
    values = expressions.resolve_parameters(_chain(n))
    assert values[f"p{n - 1}"] == pytest.approx(float(n))
    assert values["p0"] == 1.0
    # one free-name computation and one evaluation per parameter: O(N), not O(N^2)
    assert counts == {"free_names": n, "to_float": n}


def test_a_chain_of_parameters_is_resolved_with_one_evaluation_each(monkeypatch):
    _resolve_and_count(monkeypatch, 3000)


@pytest.mark.slow
def test_twenty_thousand_chained_parameters_are_resolved_in_linear_work(monkeypatch):
    _resolve_and_count(monkeypatch, 20000)


def test_a_cycle_is_reported_with_the_cycle_named():
    with pytest.raises(ModelError) as info:
        expressions.resolve_parameters({"a": "b + 1", "b": "c*2", "c": "a", "d": 1})
    assert "cycle: a -> b -> c -> a" in str(info.value)
