"""The exported C cannot be made inconsistent: every entry of its ``p`` is a value a user may change,
and a change of it is the change ``--set`` (``Model.with_values``) makes to the model.

The modal constants of a beam are integrals of its shape functions computed by quadrature from L,
the shape roots and options, stations and load profiles, times a section value (rho, EI ...): the
integrals are frozen at export (per unit section value where there is one), with every parameter
they are computed from (directly or through other parameters' expressions), outside ``p``; the
section values stay in ``p``. The oracles: flexkane's own right-hand side and outputs of the model
with the same values set (the Numba module with the changed model's constants), and the frozen
values themselves, which no editable entry may move.
"""

from __future__ import annotations

import re

import numpy as np
import pytest

import flexkane
from flexkane.builtin import builtin_text
from flexkane.c_export import c_constants, export_c
from flexkane.derivation_cache import Derivation
from flexkane.errors import ModelError
from flexkane.kane.frozen_constants import constant_roles
from flexkane.model.paths import get_value
from flexkane.numerics import evaluate_outputs
from flexkane.numerics.c_source import c_identifier

from spatial_beam_models import EI_Y, EI_Z, GJ, RHO, RHO_IP, clamped_spatial_beam
from test_c_export import CC, _call, _close, _compile, _documented, _Numba, needs_cc

#: A clamped spatial beam bending in both planes, twisting and stretching, with the rotary inertia
#: of its sections, damped, under an oblique gravity: its length is a number of the beam (frozen),
#: its section values are parameters (editable: each multiplies its integrals), its principal angle,
#: damping ratios and g are editable.
SPATIAL_BEAM = re.sub(r"(?m)^(rho|EI_y|EI_z|GJ|rho_Ip) = .*$", lambda m: f'{m[1]} = "{m[1]}_b"',
                      clamped_spatial_beam("damped-spatial-beam", """
rho_Iy = "rho_Iy_b"
rho_Iz = "rho_Iz_b"
EA = "EA_b"
n_modes_y = 1
n_modes_z = 1
n_torsion = 1
n_axial = 1
principal_angle = 0.4
damping_y = 0.02
damping_z = 0.03
torsion_damping = 0.05
""")) + f"""
[parameters]
rho_b = {RHO}
EI_y_b = {EI_Y}
EI_z_b = {EI_Z}
GJ_b = {GJ}
rho_Ip_b = {RHO_IP}
rho_Iy_b = 0.002
rho_Iz_b = 0.003
EA_b = 400.0

[gravity]
g = 9.81
direction = [0, 0.6, -0.8]
"""


def _model(name: str):
    return flexkane.loads_model(SPATIAL_BEAM) if name == "spatial-beam" else flexkane.builtin_model(name)


def _changed(model, eom):
    """Every editable entry set to a different nonzero value: the C's p and the model ``--set`` makes."""
    roles = constant_roles(eom, model)
    editable = c_constants(eom, model)[0]
    assert [c.symbol for c in editable] == roles.editable
    values = [c.value * (1.07 + 0.05 * k) if c.value else 0.01 * (k + 1) for k, c in enumerate(editable)]
    changed = model.with_values({roles.paths[c.symbol]: v for c, v in zip(editable, values)})
    return np.array([c.value for c in editable]), np.array(values), changed


@needs_cc
@pytest.mark.parametrize("name", ["falling-beam", "flexible-arm", "flexible-arm-pd", "spatial-beam"])
def test_every_entry_of_p_changes_the_c_model_as_set_changes_the_model(tmp_path, name):
    model = _model(name)
    export_c(model, tmp_path, force=True)
    prefix = c_identifier(model.name)
    lib = _compile(tmp_path, prefix)
    numba = _Numba(model)
    eom = numba.eom
    default, p, changed = _changed(model, eom)
    assert len(p) >= 3
    numbers = Derivation(changed).numbers(changed, ("p", "y0"))
    flexkane_p = np.array(numbers["p"])
    ny = len(numbers["y0"])
    outputs = list(eom.compact.outputs)
    rng = np.random.default_rng(25)
    for _ in range(3):
        t = float(rng.uniform(0.0, 0.5))
        y = np.array(numbers["y0"]) + 0.1 * rng.standard_normal(ny)
        status, dy = _call(getattr(lib, f"{prefix}_rhs"), t, y, p, ny)
        assert status == 0
        _close(dy, numba.rhs(t, y, flexkane_p), rtol=1e-10)
        status, before = _call(getattr(lib, f"{prefix}_rhs"), t, y, default, ny)
        assert status == 0 and np.max(np.abs(before - dy)) > 1e-6 * np.max(np.abs(dy))   # p is read
        status, out = _call(getattr(lib, f"{prefix}_outputs"), t, y, p, len(outputs))
        assert status == 0
        expected = evaluate_outputs(numba.module, np.array([t]), y[None, :], flexkane_p)
        _close(out, [expected[k][0] for k in outputs], rtol=1e-10)


def _nudged(model, path: str, value: float):
    """The model with the value at ``path`` 1 % larger (0.01 for a zero), else 1 % smaller (rotor-blade's
    hub inertia [0.15, 0.15, 0.3] may not grow: the triangle inequality of principal values)."""
    try:
        return model.with_values({path: 1.01 * value if value else 0.01})
    except ModelError:
        return model.with_values({path: 0.99 * value})


def _frozen(eom, model) -> np.ndarray:
    return np.array([c.value for c in c_constants(eom, model)[1]])


@pytest.mark.parametrize("name", ["falling-beam", "flexible-arm", "flexible-arm-pd", "slider-crank", "spatial-beam",
                                  *(pytest.param(name, marks=pytest.mark.slow) for name in
                                    ("falling-beam-exact", "two-link-flexible-arm", "pendulum-beam", "spin-up",
                                     "wind-mast", "rotor-blade", "spacecraft-flexible-slew",
                                     "robot-arm-3d-flexible"))])
def test_no_entry_of_p_moves_a_frozen_value_and_every_frozen_parameter_does(name):
    """Each editable entry changed alone leaves every frozen value (integrals of the shape functions,
    per unit section value) as it was, to round-off; each frozen parameter given as a number,
    changed alone, moves one (so none is frozen needlessly)."""
    model = _model(name)
    eom = Derivation(model).eom
    roles = constant_roles(eom, model)
    before, values = _frozen(eom, model), eom.constant_values(model)
    for s in roles.editable:
        after = _frozen(eom, _nudged(model, roles.paths[s], values[s]))
        np.testing.assert_allclose(after, before, rtol=1e-14, atol=0, err_msg=s.name)
    roots = [s for s in roles.frozen if s in roles.paths and not isinstance(get_value(model, roles.paths[s]), str)]
    assert roots
    for s in roots:
        after = _frozen(eom, _nudged(model, roles.paths[s], values[s]))
        assert np.max(np.abs(after - before) / np.abs(before).clip(1e-300)) > 1e-6, s


def test_header_lists_the_beam_length_frozen_and_the_section_values_in_p(tmp_path):
    """falling-beam: L gives the integrals of the shape functions, frozen per unit rho (ro) or EI;
    ro and EI stay in p and multiply them; Iz, an expression of mR, c and d, is computed from p."""
    header_path, source_path = export_c(flexkane.builtin_model("falling-beam"), tmp_path)
    header = header_path.read_text()
    editable = [n for _, n, _ in _documented(header, "p")]
    frozen = [n for _, n, _ in _documented(header, "frozen")]
    assert editable == ["EI", "b", "c", "d", "g", "mR", "ro"]
    assert {"L", "E_1/rho", "G_11/rho", "H_11/EI", "m_B/rho", "Phi_1(L)", "J_1"} <= set(frozen)
    assert not set(editable) & set(frozen) and not {"E_1", "H_11", "m_B"} & set(frozen)
    assert "#define FALLING_BEAM_NP 7" in header and f"#define FALLING_BEAM_NFROZEN {len(frozen)}" in header
    assert " *   Iz [kg m^2] = mR*(c**2 + d**2)/12" in header
    assert " *   H_11 [N/m] = EI * (H_11/EI): beam B: " in header
    assert re.search(r"frozen\[\d+\] = L \[m\] = 1\.0: parameter, the value of beams\.B\.L; the integrals", header)
    assert re.search(r"frozen\[\d+\] = m_B/rho \[m\] = 1\.0: beam B: .*, per unit beams\.B\.rho", header)
    assert "const double falling_beam_frozen_values[" in source_path.read_text()


def test_parameters_of_the_shape_functions_are_frozen_with_them(tmp_path):
    """L = 2*a: a gives the integrals through L, so both are frozen; b = a/4 - 0.025 stays an
    expression computed in C from the frozen a. A tip-mass family with mass_ratio = mR/(ro*L) makes
    its shape functions depend on mR and ro: both are frozen, EI (a factor of H_11 only) is not."""
    text = builtin_text("falling-beam").replace("L = 1.0 ", 'a = 0.5\nL = "2*a"').replace(
        "b = 0.1 ", 'b = "a/4 - 0.025"').replace('shape = { family = "clamped-free", roots = [1.875] }',
        'shape = { family = "clamped-free-tip-mass", mass_ratio = "mR/(ro*L)", inertia_ratio = 0.01 }')
    model = flexkane.loads_model(text)
    eom = Derivation(model).eom
    roles = constant_roles(eom, model)
    names = {kind: {s.name for s in getattr(roles, kind)} for kind in ("editable", "frozen")}
    assert {"a", "L", "ro", "mR", "E_1/rho", "H_11/EI"} <= names["frozen"]
    assert names["editable"] == {"EI", "c", "d", "g"}
    assert {"Iz", "b", "E_1", "H_11"} <= {s.name for s, _ in roles.derived}
    header_path, _ = export_c(model, tmp_path)
    assert re.search(r"frozen\[\d+\] = a \[[^\]]*\] = 0\.5: parameter, in parameters\.L, parameters\.b", header_path.read_text())
    if CC is not None:   # the C with its default p, and with every entry changed, is the model
        prefix = c_identifier(model.name)
        lib = _compile(tmp_path, prefix)
        numba = _Numba(model)
        default, p, changed = _changed(model, eom)
        for entries, case in ((default, model), (p, changed)):
            numbers = Derivation(case).numbers(case, ("p", "y0"))
            y = np.array(numbers["y0"]) + 0.1
            status, dy = _call(getattr(lib, f"{prefix}_rhs"), 0.1, y, entries, len(y))
            assert status == 0
            _close(dy, numba.rhs(0.1, y, np.array(numbers["p"])), rtol=1e-10)


@needs_cc
@pytest.mark.slow
def test_every_entry_of_p_of_the_flexible_3d_arm_changes_the_c_model_as_set_does(tmp_path):
    """robot-arm-3d-flexible (two spatial beams whose rho, EI, GJ, rho_Ip are parameters): its 36
    entries of p changed at once, the C against the equations of the model with those values set,
    evaluated through SymPy (13 s here; its Numba module would take minutes to compile)."""
    from spatial_control_models import Evaluated

    model = flexkane.builtin_model("robot-arm-3d-flexible")
    export_c(model, tmp_path, force=True)
    prefix = c_identifier(model.name)
    lib = _compile(tmp_path, prefix)
    eom = Derivation(model).eom
    _, p, changed = _changed(model, eom)
    assert {"EI1", "GJ2", "rho1", "rIp2"} <= {s.name for s in constant_roles(eom, model).editable}
    equations = Evaluated(eom)
    values = eom.constant_values(changed)
    equations.constants = [values[c] for c in eom.constants]
    y0 = eom.initial_state(changed)
    rng = np.random.default_rng(25)
    for _ in range(3):
        y = y0 + 0.1 * rng.standard_normal(len(y0))
        status, dy = _call(getattr(lib, f"{prefix}_rhs"), 0.2, y, p, len(y))
        assert status == 0
        _close(dy, equations.rhs(0.2, y), rtol=1e-10)


def test_a_parameter_used_only_in_other_parameters_gets_their_unit_or_says_why_not(tmp_path):
    """slider-crank: J1 appears only in Jc1 = J1 - m1*(L1/2)**2, the crank's inertia [kg m^2], so J1
    is [kg m^2]; E appears only in EA = E*bs*hs [N] and EI = E*bs*hs**3/12 [N m^2] with bs and hs
    free, so no unit is fixed and the note names those uses with their units."""
    header_path, _ = export_c(flexkane.builtin_model("slider-crank"), tmp_path)
    header = header_path.read_text()
    unit = {n: u for _, n, u in _documented(header, "p")}
    assert unit["J1"] == "kg m^2" and unit["E"] == "unit unknown"
    assert re.search(r"p\[\d+\] = E \[unit unknown\]: parameter, in parameters\.EA, parameters\.EI; no unit: its "
                     r"uses do not fix one \(parameters\.EA \[N\], parameters\.EI \[N m\^2\] leave", header)
