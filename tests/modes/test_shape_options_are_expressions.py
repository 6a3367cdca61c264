"""Numeric options of shape families are numbers or expressions of the parameters (issue 14, item 6).

A tip-mass ratio written as an expression of a tip mass follows that parameter: ``--set`` (or a
sweep variant) changes the modes and the results exactly as the literal value would, and one
derivation serves every value.
"""

import numpy as np
import pytest

import flexkane
from flexkane.commands._common import apply_settings
from flexkane.modes.from_spec import shape_family
from flexkane.modes import get_family

TEXT = """
name = "tip-mass-expression"
[parameters]
L = 1.0
EI = 2.0
rho = 0.5
M = 0.3
[beams.beam]
L = "L"
EI = "EI"
rho = "rho"
n_modes = 2
shape = { family = "clamped-free-tip-mass", mass_ratio = "M/(rho*L)", inertia_ratio = "0.1*M/(rho*L)" }
[joints.clamp]
type = "weld"
parent = "ground"
child = "beam"
[initial]
q_beam_1 = 0.01
"""


def _literal(M):
    ratio = M / 0.5
    return flexkane.loads_model(TEXT.replace('"M/(rho*L)"', repr(ratio))
                                .replace('"0.1*M/(rho*L)"', repr(0.1 * ratio))
                                .replace("M = 0.3", f"M = {M!r}"))


def _by_name(values):
    return {s.name: v for s, v in values.items()}


def test_tip_mass_ratio_expression_follows_its_parameter_through_set():
    model = flexkane.loads_model(TEXT)
    eom = flexkane.derive(model)
    before = _by_name(eom.constant_values(model))
    heavier = apply_settings(flexkane.loads_model(TEXT), ["M=0.6"])
    after = _by_name(eom.constant_values(heavier))        # the same derivation, new numbers
    literal = _literal(0.6)
    expected = _by_name(flexkane.derive(literal).constant_values(literal))
    assert after.keys() == expected.keys()
    for name in expected:
        assert after[name] == pytest.approx(expected[name], rel=1e-13, abs=1e-13), name
    # a heavier tip lowers the first frequency: H_11 / G_11 changes, and so do the modes
    assert after["H_11"] != pytest.approx(before["H_11"], rel=1e-3)
    assert after["Phi_1(L)"] != pytest.approx(before["Phi_1(L)"], rel=1e-3)
    family = shape_family(heavier.beams["beam"].shape, "beams.beam.shape", {"M": 0.6, "rho": 0.5, "L": 1.0,
                                                                             "EI": 2.0})
    np.testing.assert_array_equal(family.roots(2), get_family("clamped-free-tip-mass", mass_ratio=1.2,
                                                              inertia_ratio=0.12).roots(2))


def test_tip_mass_ratio_expression_is_not_structure():
    from flexkane.derivation_cache import structure_signature

    assert structure_signature(flexkane.loads_model(TEXT)) == structure_signature(_literal(0.6))


def test_typed_roots_and_gravity_direction_accept_expressions():
    text = """
name = "typed"
[parameters]
lam = 1.875
s = 1.0
[beams.B]
L = 1.0
EI = 2.0
rho = 0.5
n_modes = 1
shape = { family = "clamped-free", roots = ["lam"] }
[joints.clamp]
type = "weld"
parent = "ground"
child = "B"
[gravity]
g = 9.81
direction = ["0", "-s"]
"""
    model = flexkane.loads_model(text)
    values = _by_name(flexkane.derive(model).constant_values(model))
    typed = flexkane.loads_model(text.replace('["lam"]', "[1.875]"))
    assert values["H_11"] == pytest.approx(_by_name(flexkane.derive(typed).constant_values(typed))["H_11"],
                                           rel=1e-14)
    with pytest.raises(flexkane.errors.ModelError, match=r"beams\.B\.shape\.roots"):
        flexkane.loads_model(text.replace("lam = 1.875", "lam = -1.0"))
    with pytest.raises(flexkane.errors.ModelError, match=r"gravity\.direction"):
        flexkane.loads_model(text.replace("s = 1.0", "s = 0.0"))


@pytest.mark.slow
def test_results_with_an_expression_ratio_equal_those_with_the_literal_ratio():
    heavier = apply_settings(flexkane.loads_model(TEXT), ["M=0.6"])
    compiled = flexkane.compile_model(flexkane.derive(heavier))
    kwargs = dict(t_end=0.5, dt_out=0.05, rtol=1e-10, atol=1e-12)
    res = flexkane.simulate(compiled, model=heavier, **kwargs)
    lit = flexkane.simulate(compiled, model=_literal(0.6), **kwargs)
    light = flexkane.simulate(compiled, model=flexkane.loads_model(TEXT), **kwargs)
    np.testing.assert_allclose(res["tip_beam"], lit["tip_beam"], rtol=0, atol=1e-12)
    assert np.max(np.abs(res["tip_beam"] - light["tip_beam"])) > 1e-4


@pytest.mark.slow
def test_a_sweep_over_the_tip_mass_updates_the_modes(tmp_path):
    from flexkane.sweep import SweepSpec, read_table, run_sweep

    spec = SweepSpec(vary=("M=0.3,0.6",), t_end=0.5, dt_out=0.05, rtol=1e-10, atol=1e-12, save_trajectories=True)
    outcome = run_sweep(flexkane.loads_model(TEXT), spec, out=tmp_path / "sweep", workers=1)
    assert outcome.structures == 1
    rows = {row["M"]: row for row in read_table(tmp_path / "sweep", as_rows=True)}
    tips = {M: flexkane.load_results(tmp_path / "sweep" / "variants" / rows[M]["variant"])["tip_beam"]
            for M in (0.3, 0.6)}
    literal = _literal(0.6)
    expected = flexkane.simulate(flexkane.compile_model(flexkane.derive(literal)), model=literal, t_end=0.5,
                                 dt_out=0.05, rtol=1e-10, atol=1e-12)["tip_beam"]
    np.testing.assert_allclose(tips[0.6], expected, rtol=0, atol=1e-12)
    assert np.max(np.abs(tips[0.6] - tips[0.3])) > 1e-4
