"""Warnings where a run leaves the validity of its model (issue 14, item 8)."""

import numpy as np
import pytest

import flexkane
from flexkane.cli import main
from flexkane.validity import validity_warnings


def _warnings(model, t, set_state):
    eom = flexkane.derive(model)
    state = np.zeros((len(t), len(eom.state_names)))
    for name, column in set_state.items():
        state[:, eom.state_names.index(name)] = column
    return validity_warnings(eom, model, np.asarray(t, dtype=float), state, eom.constant_values(model))


def test_a_deflection_beyond_a_tenth_of_the_length_is_warned_about():
    model = flexkane.builtin_model("spin-up-linear")              # L = 10 m
    t = [0.0, 1.0, 2.0]
    (warning,) = [w for w in _warnings(model, t, {"q_beam_1": [0.0, 0.2, 0.6]}) if "deflection" in w]
    # Phi_1(L) = 2: the tip is at 1.2 m at t = 2 s, 12 % of the length
    assert "beam 'beam'" in warning and "1.2 m" in warning and "t = 2 s" in warning
    model.simulation.deflection_warning = 0.15
    assert not [w for w in _warnings(model, t, {"q_beam_1": [0.0, 0.2, 0.6]}) if "deflection" in w]
    with pytest.raises(flexkane.errors.ModelError, match="simulation.deflection_warning"):
        model.simulation.deflection_warning = -1.0
        model.validate()


def test_a_fast_spin_without_geometric_stiffening_is_warned_about_naming_the_option():
    model = flexkane.builtin_model("spin-up-linear")              # p1 = 3.80 rad/s, driven spin
    slow = _warnings(model, [0.0, 0.5], {})                       # spin 0.003 rad/s at most
    assert slow == []
    (warning,) = _warnings(model, [0.0, 10.0, 20.0], {})          # up to 6 rad/s
    assert "geometric_stiffening" in warning and "6 rad/s" in warning and "3.8 rad/s" in warning
    stiffened = flexkane.builtin_model("spin-up")                 # the same beam with stiffening
    assert _warnings(stiffened, [0.0, 10.0, 20.0], {}) == []


def test_warnings_of_a_variant_use_its_numbers_and_leave_the_equations_alone():
    """A sweep variant (EI given as a number instead of a parameter) with the base model's equations."""
    base = flexkane.builtin_model("falling-beam-exact")
    eom = flexkane.derive(base)
    variant = base.copy()
    variant.beams["B"].EI = 20.0
    variant.validate()
    constants = list(eom.constants)
    state = np.zeros((2, len(eom.state_names)))
    state[1, eom.state_names.index("q4")] = 0.2                  # Phi_1(L) q4 = 0.4 m on a 1 m beam
    (warning,) = validity_warnings(eom, variant, np.array([0.0, 1.0]), state, eom.constant_values(variant))
    assert "beam 'B'" in warning and "0.4 m" in warning
    assert list(eom.constants) == constants


def test_the_chapters_example_runs_without_warning(tmp_path):
    assert main(["run", "falling-beam", "--out", str(tmp_path / "run"), "--quiet", "--t-end", "1"]) == 0
    assert flexkane.load_results(tmp_path / "run").warnings == []


@pytest.mark.slow
def test_spin_up_linear_run_reports_its_divergence(tmp_path, capsys):
    assert main(["run", "spin-up-linear", "--out", str(tmp_path / "run"), "--quiet"]) == 0
    err = capsys.readouterr().err
    assert "warning: beam 'beam': its deflection reached" in err
    assert "geometric_stiffening = true" in err
    stored = flexkane.load_results(tmp_path / "run").warnings
    assert any("deflection reached" in w for w in stored) and any("geometric_stiffening" in w for w in stored)
