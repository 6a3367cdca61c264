"""The exported C cannot be made inconsistent: every entry of its ``p`` is a value a user may change,
and a change of it is the change ``--set`` (``Model.with_values``) makes to the model.

The modal constants of a beam are integrals of its shape functions computed by quadrature from L,
rho, EI ...; they are frozen at export, with every parameter they are computed from (directly or
through other parameters' expressions), outside ``p``. The oracles: flexkane's own right-hand side
and outputs of the model with the same values set (the Numba module with the changed model's
constants), and the modal constants themselves, which no editable entry may move.
"""

from __future__ import annotations

import re

import numpy as np
import pytest

import flexkane
from flexkane.builtin import builtin_text
from flexkane.c_export import c_constants, export_c
from flexkane.derivation_cache import Derivation
from flexkane.kane.frozen_constants import constant_roles
from flexkane.model.paths import get_value
from flexkane.numerics import evaluate_outputs
from flexkane.numerics.c_source import c_identifier

from spatial_beam_models import clamped_spatial_beam
from test_c_export import CC, _call, _close, _compile, _documented, _Numba, needs_cc

#: A clamped spatial beam bending in both planes and twisting, damped, under an oblique gravity:
#: its length, rigidities and masses are numbers of the beam (frozen), its principal angle, damping
#: ratios and g are editable.
SPATIAL_BEAM = clamped_spatial_beam("damped-spatial-beam", """
n_modes_y = 1
n_modes_z = 1
n_torsion = 1
principal_angle = 0.4
damping_y = 0.02
damping_z = 0.03
torsion_damping = 0.05
""") + """
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


@pytest.mark.parametrize("name", ["falling-beam", "flexible-arm", "flexible-arm-pd", "slider-crank",
                                  "spatial-beam"])
def test_no_entry_of_p_moves_a_modal_constant_and_every_frozen_parameter_does(name):
    """Each editable entry changed alone leaves every modal constant as it was; each frozen parameter
    given as a number, changed alone, moves one (so none is frozen needlessly)."""
    model = _model(name)
    eom = Derivation(model).eom
    roles = constant_roles(eom, model)
    before = eom.constant_values(model)
    for s in roles.editable:
        value = before[s]
        after = eom.constant_values(model.with_values({roles.paths[s]: 1.01 * value if value else 0.01}))
        assert all(after[m] == before[m] for m in roles.modal), s
    roots = [s for s in roles.frozen if s not in roles.modal and s in roles.paths
             and not isinstance(get_value(model, roles.paths[s]), str)]
    assert roots
    for s in roots:
        after = eom.constant_values(model.with_values({roles.paths[s]: 1.01 * before[s]}))
        assert any(after[m] != before[m] for m in roles.modal), s


def test_header_lists_the_beam_values_frozen_and_keeps_them_out_of_p(tmp_path):
    """falling-beam: L, EI and rho (the parameter ro) give the modal constants; Iz, an expression of
    mR, c and d, is computed from p on every call."""
    header_path, source_path = export_c(flexkane.builtin_model("falling-beam"), tmp_path)
    header = header_path.read_text()
    editable = [n for _, n, _ in _documented(header, "p")]
    frozen = [n for _, n, _ in _documented(header, "frozen")]
    assert editable == ["b", "c", "d", "g", "mR"]
    assert {"L", "EI", "ro", "E_1", "G_11", "H_11", "Phi_1(L)"} <= set(frozen)
    assert not set(editable) & set(frozen)
    assert "#define FALLING_BEAM_NP 5" in header and f"#define FALLING_BEAM_NFROZEN {len(frozen)}" in header
    assert " *   Iz [kg m^2] = mR*(c**2 + d**2)/12" in header
    assert re.search(r"frozen\[\d+\] = L \[m\] = 1\.0: parameter, the value of beams\.B\.L; the modal", header)
    assert "const double falling_beam_frozen_values[" in source_path.read_text()


def test_a_parameter_a_beam_length_is_computed_from_is_frozen_with_it(tmp_path):
    """L = 2*a: a gives the modal constants through L, so both are frozen; b = a/4 + 0.05 stays an
    expression computed in C from the frozen a, and mR, which feeds Iz only, stays editable."""
    text = builtin_text("falling-beam").replace("L = 1.0 ", 'a = 0.5\nL = "2*a"').replace(
        "b = 0.1 ", 'b = "a/4 - 0.025"')
    model = flexkane.loads_model(text)
    eom = Derivation(model).eom
    roles = constant_roles(eom, model)
    names = {kind: {s.name for s in getattr(roles, kind)} for kind in ("editable", "frozen")}
    assert {"a", "L", "EI", "ro"} <= names["frozen"] and names["editable"] == {"c", "d", "g", "mR"}
    assert [s.name for s, _ in roles.derived] == ["Iz", "b"]
    header_path, _ = export_c(model, tmp_path)
    assert re.search(r"frozen\[\d+\] = a \[unit unknown\] = 0\.5: parameter;", header_path.read_text())
    if CC is not None:   # the C with its default p is the model
        prefix = c_identifier(model.name)
        lib = _compile(tmp_path, prefix)
        numba = _Numba(model)
        numbers = numba.derivation.numbers(model, ("p", "y0"))
        y = np.array(numbers["y0"]) + 0.1
        status, dy = _call(getattr(lib, f"{prefix}_rhs"), 0.1, y, [c.value for c in c_constants(eom, model)[0]], len(y))
        assert status == 0
        _close(dy, numba.rhs(0.1, y, np.array(numbers["p"])), rtol=1e-12)
