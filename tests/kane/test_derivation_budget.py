"""The derivation as a whole has a time and a size budget (flexkane.kane.budget): exceeding either
is a ModelError naming the budget and how to raise it; a derivation within both is unchanged."""

import pytest

import flexkane
from flexkane.cli import main
from flexkane.errors import ModelError
from flexkane.kane import budget
from flexkane.kane.equations import derive


def test_the_size_budget_stops_a_derivation_whose_equations_are_too_large(monkeypatch):
    monkeypatch.setenv("FLEXKANE_DERIVE_NODES", "100")
    with pytest.raises(ModelError) as info:
        derive(flexkane.builtin_model("flexible-arm"))
    assert info.value.path == "derivation"
    assert "at most 100 distinct subexpressions" in str(info.value)
    assert "FLEXKANE_DERIVE_NODES" in str(info.value)


def test_the_time_budget_stops_a_derivation_that_runs_too_long(monkeypatch):
    clock = iter(range(0, 10_000, 50))   # a fake clock: 50 s pass between two readings
    monkeypatch.setattr(budget.time, "monotonic", lambda: float(next(clock)))
    monkeypatch.setenv("FLEXKANE_DERIVE_SECONDS", "120")
    with pytest.raises(ModelError) as info:
        derive(flexkane.builtin_model("flexible-arm"))
    assert "time budget of 120 s" in str(info.value) and "FLEXKANE_DERIVE_SECONDS" in str(info.value)


def test_a_budget_exceeded_exits_2_from_the_command_line(monkeypatch, capsys, tmp_path):
    monkeypatch.setenv("FLEXKANE_CACHE_DIR", str(tmp_path))   # an empty cache: the derivation must run
    monkeypatch.setenv("FLEXKANE_DERIVE_NODES", "50")
    assert main(["derive", "pendulum-beam"]) == 2
    err = capsys.readouterr().err   # the derivation announced (flexkane.progress), then refused
    assert err.startswith("flexkane: deriving the equations of motion of pendulum-beam ...\n"
                          "flexkane: error: derivation: expected equations of at most 50")


def test_a_bad_budget_setting_is_refused(monkeypatch):
    monkeypatch.setenv("FLEXKANE_DERIVE_SECONDS", "soon")
    with pytest.raises(ModelError) as info:
        budget.DerivationBudget()
    assert info.value.path == "FLEXKANE_DERIVE_SECONDS"


def test_the_default_budgets_let_every_example_derive_unchanged(monkeypatch):
    monkeypatch.delenv("FLEXKANE_DERIVE_NODES", raising=False)
    monkeypatch.delenv("FLEXKANE_DERIVE_SECONDS", raising=False)
    eom = derive(flexkane.builtin_model("flexible-arm"))
    monkeypatch.setenv("FLEXKANE_DERIVE_NODES", str(10**9))
    again = derive(flexkane.builtin_model("flexible-arm"))
    assert list(eom.mass_matrix) == list(again.mass_matrix) and list(eom.forcing) == list(again.forcing)
