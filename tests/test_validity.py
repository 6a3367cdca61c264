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


#: A hub turning about the ground's z carrying a 1 m spatial beam along x that bends in both planes:
#: the 3D counterpart of spin-up-linear's beam, to check that the validity warnings are those of planar
#: beams (one mechanism for both). First bending frequencies (clamped-free, eq. 8.7):
#: p1 = 1.8751^2 sqrt(EI/rho) = 3.516 rad/s along y (EI_z = 1) and 7.032 rad/s along z (EI_y = 4).
SPINNING_BEAM_3D = """
dimensions = 3
name = "spinning-beam-3d"
[bodies.hub]
mass = 1.0
inertia = [0.1, 0.1, 0.1]
[beams.arm]
L = 1.0
rho = 1.0
EI_y = 4.0
EI_z = 1.0
n_modes_y = 1
n_modes_z = 1
{stiffening}
[joints.spin]
type = "revolute"
parent = "ground"
child = "hub"
axis = [0, 0, 1]
[joints.clamp]
type = "weld"
parent = "hub"
child = "arm"
"""


def _spatial_warnings(t, set_state, stiffening=""):
    model = flexkane.loads_model(SPINNING_BEAM_3D.format(stiffening=stiffening))
    return _warnings(model, t, set_state)


def test_a_spatial_beam_deflecting_beyond_a_tenth_of_its_length_is_warned_about():
    # Phi_1(L) = 2 for the clamped-free mode: v(L) = 0.6 m along y and w(L) = 1.0 m along z, the
    # deflection vector 1.166 m long on a 1 m beam
    t = [0.0, 1.0, 2.0]
    (warning,) = [w for w in _spatial_warnings(t, {"q_arm_y1": [0.0, 0.01, 0.3], "q_arm_z1": [0.0, 0.0, 0.5]})
                  if "deflection" in w]
    assert "beam 'arm'" in warning and "1.17 m" in warning and "L = 1 m" in warning and "t = 2 s" in warning
    # each plane alone is checked: 0.2 m along z only
    (warning,) = _spatial_warnings(t, {"q_arm_z1": [0.0, 0.0, 0.1]})
    assert "0.2 m" in warning
    assert _spatial_warnings(t, {"q_arm_y1": [0.0, 0.01, 0.02]}) == []   # 4 cm: within 10 %


def test_a_spatial_beam_spun_fast_without_geometric_stiffening_is_warned_about_naming_the_option():
    t = [0.0, 1.0, 2.0]
    assert _spatial_warnings(t, {"u_spin": [0.0, 0.1, 0.3]}) == []                 # below 0.35 rad/s
    (warning,) = _spatial_warnings(t, {"u_spin": [0.0, 0.1, 2.0]})
    # the lower of the two planes' first frequencies, 3.516 rad/s (along y, EI_z = 1)
    assert "geometric_stiffening = true in [beams.arm]" in warning and "2 rad/s" in warning \
        and "p1 = 3.52 rad/s" in warning
    assert _spatial_warnings(t, {"u_spin": [0.0, 0.1, 2.0]}, "geometric_stiffening = true") == []


@pytest.mark.slow
def test_a_run_of_a_spatial_beam_warns_through_its_compiled_spin_rates():
    """The compiled path: the transverse spin sqrt(w_y^2 + w_z^2) of the root frame is generated code."""
    text = SPINNING_BEAM_3D.format(stiffening="") + ("[initial]\nu_spin = 2.0\nq_arm_z1 = 0.6\n"
                                                     "[simulation]\nt_end = 0.5\ndt_out = 0.1\n")
    results = flexkane.simulate(flexkane.compile_model(flexkane.derive(flexkane.loads_model(text))))
    deflection, spin = results.warnings
    assert "beam 'arm': its deflection reached 1.2 m" in deflection
    assert "p1 = 3.52 rad/s" in spin and "geometric_stiffening = true in [beams.arm]" in spin
