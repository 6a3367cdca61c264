"""The notebook variant's beam forms on spatial beams: the weight at the deformed midpoint and the
elastic forces through the root's moment and shear (eq. 8.28) in each bending plane.

Oracle: the Galerkin equations of that discretisation written here with NumPy quadrature of the
shape functions: a clamped beam's static deflection in both principal planes under its weight at
the midpoint, ``K^p q_p = m_B (g . e_p) Phi(L/2)`` with ``K^p_ji = EI_p int Phi_j Phi_i'''' dx``.
"""

from __future__ import annotations

import numpy as np
import pytest

import flexkane
from flexkane.errors import ModelError
from flexkane.model import loads_model
from flexkane.model.parts import ShapeSpec
from flexkane.modes.from_spec import shape_family
from spatial_models import accelerations

ROOTS = [1.875, 4.694]     # the notebook's rounded roots: not exact modes, so eq. 8.28 differs from 8.31

CLAMPED = """
dimensions = 3
name = "clamped-notebook-beam"

[beams.B]
L = 1.2
rho = 0.8
EI_y = 20.0
EI_z = 45.0
n_modes_y = 2
n_modes_z = 2
shape_y = {{ family = "clamped-free", roots = {roots} }}
shape_z = {{ family = "clamped-free", roots = {roots} }}
principal_angle = 0.4
gravity = "midpoint"
elastic_forces = "shear-moment"
{extra}

[joints.clamp]
type = "weld"
parent = "ground"
child = "B"

[gravity]
g = 9.81
direction = [0.3, -1.0, -0.6]
"""


def _galerkin(L, EI, n=2):
    """``K_ji = EI int Phi_j Phi_i'''' dx`` (eq. 8.28's distributed load), ``H_ji = EI int Phi_j'' Phi_i'' dx``
    (eq. 8.32) and ``Phi_j(L/2)`` of the clamped-free functions with the notebook's roots."""
    family = shape_family(ShapeSpec("clamped-free", ROOTS), "shape")
    xi, w = np.polynomial.legendre.leggauss(40)
    xi, w = (xi + 1) / 2, w * L / 2
    phi, d2, d4 = (family.phi(xi, n, k) / L ** k for k in (0, 2, 4))
    K = EI * np.einsum("k,jk,ik->ji", w, phi, d4)
    H = EI * np.einsum("k,jk,ik->ji", w, d2, d2)
    return K, H, family.phi(np.array([0.5]), n, 0)[:, 0]


def test_clamped_spatial_beam_sags_in_both_planes_as_the_notebook_discretisation():
    """The clamped beam (principal axes turned by 0.4 rad, EI_y != EI_z) at the deflection the test
    computes, ``q_p = (K^p)^-1 m_B (g . e_p) Phi(L/2)`` in each plane, is at rest (u' = 0 to 1e-10 of
    the weight's accelerations); the strain-energy form's deflection (eq. 8.31) would not be."""
    eom = flexkane.derive(loads_model(CLAMPED.format(roots=ROOTS, extra="")), cache=False)
    assert [q.name for q in eom.q] == ["q_B_y1", "q_B_y2", "q_B_z1", "q_B_z2"]
    g = 9.81 * np.array([0.3, -1.0, -0.6]) / np.linalg.norm([0.3, -1.0, -0.6])
    c, s = np.cos(0.4), np.sin(0.4)
    y_p, z_p = np.array([0.0, c, s]), np.array([0.0, -s, c])
    mass = 0.8 * 1.2
    deflection, energy_form = [], []
    for axis, EI in ((y_p, 45.0), (z_p, 20.0)):      # plane y bends about z_p (EI_z), plane z about y_p
        K, H, middle = _galerkin(1.2, EI)
        load = mass * (g @ axis) * middle
        deflection.append(np.linalg.solve(K, load))
        energy_form.append(np.linalg.solve(H, load))
    q_star, q_energy = np.concatenate(deflection), np.concatenate(energy_form)
    rhs = accelerations(eom)
    u = np.zeros(4)
    scale = np.abs(rhs(np.zeros(4), u)).max()           # the weight alone
    assert scale > 1.0
    assert np.abs(rhs(q_star, u)).max() <= 1e-10 * scale
    assert np.abs(rhs(q_energy, u)).max() > 1e-6 * scale     # 2.8e-5: the rounded roots


@pytest.mark.parametrize("extra, path, words", [
    ("geometric_stiffening = true", "beams.B.elastic_forces", "'strain-energy' with geometric_stiffening"),
    ('n_axial = 1\nEA = 1e5', "beams.B.elastic_forces", "axial modes"),
])
def test_shear_moment_forces_of_a_spatial_beam_without_stiffening_or_stretch_only(extra, path, words):
    with pytest.raises(ModelError) as info:
        loads_model(CLAMPED.format(roots=ROOTS, extra=extra))
    assert info.value.path == path and words in str(info.value)


def test_a_spatial_beam_names_its_gravity_model_from_the_choices():
    text = CLAMPED.format(roots=ROOTS, extra="").replace('gravity = "midpoint"', 'gravity = "midpiont"')
    with pytest.raises(ModelError) as info:
        loads_model(text)
    assert info.value.path == "beams.B.gravity" and "'distributed', 'midpoint'" in str(info.value)


def test_equations_report_defines_the_constants_of_the_root_moment_and_shear():
    """equations.md of the notebook beam on a hinge (a skew axis, so both planes' root moments act)
    defines Phi''(0) and the integrals of Phi'''' of both planes and writes its rigidities by name."""
    from flexkane.report import constant_columns, equations_markdown

    text = CLAMPED.format(roots=ROOTS, extra="").replace('type = "weld"', 'type = "revolute"\naxis = [0, 1, 1]')
    eom = flexkane.derive(loads_model(text), cache=False)
    report = equations_markdown(eom, eom.constant_values())
    definitions = {name: (definition, unit) for _, name, kind, _, _, definition, unit in constant_columns(eom)
                   if kind == "modal"}
    assert definitions["JPhi_z1_z2"] == (r"\int_0^L \Phi^{z}_{1}\,\Phi^{z}_{2}''''\,dx", "1/m^3")
    assert definitions["Phi_y1''(0)"] == (r"\Phi^{y}_{1}''(0)", "1/m^2")
    assert r"\mathrm{EI}_{z,B} \Phi_{y1}''(0)" in report and r"\mathrm{EI}_{y,B} \Phi_{z1}''(0)" in report


def test_the_forms_are_structure_a_spatial_model_file_keeps():
    """The forms change the equations: the derivation cache's structure signature tells them apart,
    and a spatial model file writes and reads them back."""
    from flexkane.derivation_cache import structure_signature
    from flexkane.model import dumps_model

    model = loads_model(CLAMPED.format(roots=ROOTS, extra=""))
    assert loads_model(dumps_model(model)) == model
    signatures = {structure_signature(model)}
    for key, default in (("gravity", "distributed"), ("elastic_forces", "strain-energy")):
        other = model.copy()
        setattr(other.beams["B"], key, default)
        signatures.add(structure_signature(other))
    assert len(signatures) == 3
