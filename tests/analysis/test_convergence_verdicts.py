"""Convergence studies say whether each quantity converged (relative change per added count of modes
against a stated tolerance), and study mode counts below the ones a model's [initial] sets."""

from __future__ import annotations

import csv
import math

import pytest

import flexkane
from flexkane.analysis.convergence import DEFAULT_TOLERANCE, convergence_verdict
from flexkane.cli import main
from flexkane.errors import ModelError
from flexkane.model.coordinates import coordinate_names


# ---------------------------------------------------------------- the verdict on given sequences
def test_quantity_whose_last_change_is_within_the_tolerance_converged_where_the_changes_stayed_within():
    verdict = convergence_verdict([100.0, 90.0, 89.95, 89.949], [1, 2, 3, 4], 1e-3, "bending 1")
    assert verdict.converged is True and verdict.n_modes == 3
    assert verdict.change == pytest.approx(0.05 / 89.95)          # the largest change from n = 3 on
    assert verdict.text == "converged to 5.6e-04 relative at n = 3"


def test_quantity_whose_last_change_exceeds_the_tolerance_has_not_converged():
    verdict = convergence_verdict([100.0, 90.0, 85.0], [1, 2, 3])
    assert verdict.converged is False and verdict.tolerance == DEFAULT_TOLERANCE == 1e-3
    assert verdict.change == pytest.approx(5.0 / 85.0)
    assert verdict.text == "not converged: last change 5.9e-02 > 0.001"


def test_a_larger_tolerance_turns_the_same_sequence_converged_from_an_earlier_count():
    values, counts = [100.0, 90.0, 85.0], [2, 4, 6]
    assert convergence_verdict(values, counts, 0.1).text == "converged to 5.9e-02 relative at n = 6"
    assert convergence_verdict(values, counts, 0.2).text == "converged to 1.1e-01 relative at n = 4"


def test_a_small_change_before_a_large_one_does_not_count():
    verdict = convergence_verdict([100.0, 99.99, 95.0, 94.999], [1, 2, 3, 4])
    assert verdict.converged is True and verdict.n_modes == 4


def test_a_quantity_known_at_fewer_than_the_last_two_counts_is_not_judged():
    for values in ([5.0], [4.0, math.nan], [math.nan, 5.0]):
        verdict = convergence_verdict(values, list(range(1, len(values) + 1)))
        assert verdict.converged is None and math.isnan(verdict.change)
        assert verdict.text.startswith("not judged")


def test_a_quantity_that_stays_zero_converged_and_one_that_leaves_zero_did_not():
    assert convergence_verdict([0.0, 0.0], [1, 2]).converged is True
    assert convergence_verdict([1e-9, 0.0], [1, 2]).converged is False


@pytest.mark.parametrize("tolerance", [0.0, -1e-3, 1.0, math.nan, math.inf, True, "1e-3"])
def test_a_tolerance_that_is_not_a_relative_change_is_refused_naming_the_option(tolerance):
    with pytest.raises(ModelError, match="--tolerance"):
        convergence_verdict([1.0, 1.0], [1, 2], tolerance)


def test_converge_refuses_a_bad_tolerance_before_deriving(tmp_path, capsys):
    code = main(["converge", str(tmp_path / "no-such-model.toml"), "--n-modes", "1..2", "--tolerance", "0"])
    err = capsys.readouterr().err
    assert code == 2 and "--tolerance" in err and "between 0 and 1" in err and "Traceback" not in err


# ---------------------------------------------------------------- initial values of the modes studied
def test_with_modes_drops_the_initial_values_of_modes_beyond_the_count():
    model = flexkane.builtin_model("rotor-blade")       # [initial] equilibrium = true: the search's start
    model.initial.update({"q_blade_z1": -7.564e-3, "q_blade_z2": -1.0667e-4})
    assert model.initial_beyond_modes(1) == ["q_blade_z2"] and model.initial_beyond_modes(2) == []
    one = model.with_modes(1).validate()
    assert one.initial == {"equilibrium": True, "q_blade_z1": model.initial["q_blade_z1"]}
    assert model.with_modes(3).validate().initial == model.initial


def test_with_modes_keeps_each_initial_value_on_its_coordinate_when_sequential_numbers_shift():
    model = flexkane.builtin_model("two-link-flexible-arm")     # shoulder, upper's 2 modes, elbow, fore's 2 modes
    model.naming = "sequential"
    model.initial = {"q4": 0.5, "q3": 0.01, "u2": 0.3}          # the elbow, upper's mode 2, upper's mode 1
    assert model.initial_beyond_modes(1) == ["q3"]
    for n, elbow in ((1, "q3"), (2, "q4"), (3, "q5")):
        variant = model.with_modes(n).validate()
        names = {(c.owner, c.index): c.q for c in coordinate_names(variant)}
        assert names[("elbow", 0)] == elbow and variant.initial[elbow] == 0.5
        assert variant.initial["u2"] == 0.3
        assert variant.initial.get(names.get(("upper", 2))) == (0.01 if n > 1 else None)
        assert sorted(variant.initial.values()) == sorted([0.5, 0.3] + [0.01] * (n > 1))


def test_converge_studies_counts_below_the_initial_modes_with_a_note_and_verdicts(tmp_path, capsys):
    out = tmp_path / "c"
    code = main(["converge", "flexible-arm", "--set", "q_link_2=0.001", "--set", "u_link_2=0.1", "--n-modes",
                 "1..2", "--tolerance", "0.05", "--count", "1", "--out", str(out)])
    printed = capsys.readouterr().out
    assert code == 0
    assert "note: n = 1: the initial values of q_link_2, u_link_2 are dropped" in printed and "--n-modes" in printed
    assert "tolerance: 0.05 relative change per added count of modes" in printed
    assert "bending 1: converged to " in printed and "relative at n = 2" in printed
    with open(out / "convergence_verdicts.csv", newline="") as handle:
        rows = list(csv.DictReader(handle))
    assert [(r["quantity"], r["converged"], r["n_modes"]) for r in rows] == [("bending 1", "true", "2")]
    assert float(rows[0]["tolerance [-]"]) == 0.05 and rows[0]["verdict"] in printed


def test_a_mode_count_a_model_cannot_have_is_reported_naming_n_modes(tmp_path, capsys):
    # falling-beam types the root of its one shape function: two modes need two roots
    assert main(["converge", "falling-beam", "--n-modes", "2", "--out", str(tmp_path / "c")]) == 2
    err = capsys.readouterr().err
    assert err.startswith("flexkane: error: --n-modes") and "shape.roots" in err and "Traceback" not in err
    assert main(["check", "falling-beam", "--n-modes", "2"]) == 2
    assert capsys.readouterr().err.startswith("flexkane: error: --n-modes")
