"""Modal analysis of spatial models with beams: frequencies, labelled mode shapes, rigid-body modes.

Oracles: the clamped frequencies of a spatial beam (eq. 8.7 with EI_y for the deflection along z and
EI_z for the one along y; torsion pi/(2L) sqrt(GJ/rho_Ip)); the shape functions of the families
(the drawn fields of a mode); and the count of modes: a chain with n speeds has n modes (rigid-body,
oscillatory, or two real eigenvalues each), of which a free body has six rigid-body modes at rest
but only those along and about the spin axis when it spins freely (the others are oscillations at
the spin rate seen from the spinning frame).
"""

from __future__ import annotations

import csv

import numpy as np
import pytest

from flexkane.analysis import Linearization, modal_analysis
from flexkane.analysis.mode_plot import SpatialBeamShapes, plot_mode_shapes
from flexkane.model import loads_model
from flexkane.modes import get_family
from spatial_beam_models import EI_Y, EI_Z, GJ, L, RHO, RHO_IP, clamped_spatial_beam

LAMBDA_1 = 1.8751040687119611

CLAMPED = clamped_spatial_beam("clamped-spatial-beam", """
n_modes_y = 1
n_modes_z = 1
n_torsion = 1
principal_angle = 0.3
""", orientation=((1, 2, 0.5), 0.7))


def mode_count(modal) -> float:
    """Modes of a modal analysis: rigid and oscillatory ones once, real eigenvalues by halves."""
    return sum(1.0 if m.kind in ("rigid", "oscillatory") else 0.5 for m in modal.modes)


@pytest.fixture(scope="module")
def clamped():
    return modal_analysis(Linearization(loads_model(CLAMPED), about="equilibrium").at(outputs=False))


def test_clamped_spatial_beam_modes_have_analytic_frequencies_and_labels(clamped):
    frequency = {m.label: m.omega for m in clamped.modes}
    assert sorted(frequency) == ["bending y 1", "bending z 1", "torsion 1"]
    assert frequency["bending z 1"] == pytest.approx(LAMBDA_1 ** 2 * np.sqrt(EI_Y / (RHO * L ** 4)), rel=1e-9)
    assert frequency["bending y 1"] == pytest.approx(LAMBDA_1 ** 2 * np.sqrt(EI_Z / (RHO * L ** 4)), rel=1e-9)
    assert frequency["torsion 1"] == pytest.approx(np.pi / (2 * L) * np.sqrt(GJ / RHO_IP), rel=1e-9)
    assert not clamped.rigid
    assert "bending z 1 (100 %)" in clamped.table()
    rows = list(csv.DictReader(clamped.csv_text().splitlines()))
    assert [r["motion"] for r in rows] == ["bending z 1", "bending y 1", "torsion 1"]
    assert float(rows[2]["participation torsion"]) == pytest.approx(1.0, abs=1e-12)


def test_mode_shape_fields_along_a_spatial_beam_are_the_shape_functions(clamped):
    shapes = SpatialBeamShapes(clamped.linear, points=11)
    xi = np.linspace(0.0, 1.0, 11)
    tip = get_family("clamped-free").phi(xi, 1)[0]
    twist = get_family("torsion-clamped-free").phi(xi, 1)[0]
    by_label = {m.label: shapes.fields(m.shape)["b"] for m in clamped.modes}
    np.testing.assert_allclose(shapes.beams["b"][0], L * xi)
    np.testing.assert_allclose(np.abs(by_label["bending z 1"]["w"]), np.abs(tip), atol=1e-12)
    np.testing.assert_allclose(by_label["bending z 1"]["v"], 0.0, atol=1e-12)
    np.testing.assert_allclose(np.abs(by_label["torsion 1"]["theta"]), np.abs(twist), atol=1e-12)
    np.testing.assert_allclose(by_label["torsion 1"]["w"], 0.0, atol=1e-12)


def test_about_rest_starts_from_the_undeformed_spatial_beam():
    """About rest the elastic coordinates of the start are zeroed for every role of a spatial beam
    (bending along y and z, torsion), not only the planar ones: the clamped beam given deflections
    and a twist at rest is undeformed (q = 0, an equilibrium without gravity) and has its clamped
    frequencies."""
    model = loads_model(CLAMPED + "\n[initial]\nq_b_y1 = 0.01\nq_b_z1 = -0.02\nq_b_t1 = 0.03\n")
    linearization = Linearization(model, about="rest")
    assert sorted(q.name for q in linearization.q_all) == ["q_b_t1", "q_b_y1", "q_b_z1"]
    assert np.abs(linearization.q_initial).min() > 0     # the start is deformed
    check = linearization.operating_point()
    assert check.ok and np.abs(check.q).max() == 0.0
    modal = modal_analysis(linearization.at(outputs=False))
    frequency = {m.label: m.omega for m in modal.modes}
    assert frequency["torsion 1"] == pytest.approx(np.pi / (2 * L) * np.sqrt(GJ / RHO_IP), rel=1e-9)


@pytest.mark.slow
def test_linearize_command_draws_and_labels_the_modes_of_a_spatial_beam(clamped, tmp_path, capsys):
    from flexkane.cli import main

    path = tmp_path / "clamped.toml"
    path.write_text(CLAMPED)
    out = tmp_path / "lin"
    assert main(["linearize", str(path), "--out", str(out)]) == 0
    assert "torsion 1 (100 %)" in capsys.readouterr().out
    assert (out / "mode_shapes.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    rows = list(csv.DictReader((out / "modes.csv").read_text().splitlines()))
    assert [r["motion"] for r in rows] == ["bending z 1", "bending y 1", "torsion 1"]
    assert plot_mode_shapes(clamped, tmp_path / "modes.png", count=1).exists()


TORQUE_FREE = """
name = "torque-free"
dimensions = 3
[bodies.box]
mass = 2.0
inertia = [1.0, 2.0, 2.5]
[joints.pivot]
type = "{joint}"
parent = "ground"
parent_position = [0, 0, 0]
child = "box"
"""


@pytest.mark.parametrize("joint, rigid_at_rest, rigid_spinning", [("spherical", 3, 1), ("free", 6, 2)])
def test_a_freely_spinning_body_keeps_only_its_rigid_body_modes_along_the_spin(joint, rigid_at_rest, rigid_spinning):
    """At rest every direction of a free body is a rigid-body mode; spinning about its major axis, only
    the turn about (and, free, the shift along) that axis: the other turns are seen from the spinning
    frame as oscillations at the spin rate (and the other shifts too), so the modes still number the
    speeds (the null space of K alone counted six rigid-body modes besides those oscillations)."""
    model = loads_model(TORQUE_FREE.format(joint=joint))
    rest = modal_analysis(Linearization(model, about="rest").at(outputs=False))
    assert len(rest.rigid) == rigid_at_rest == mode_count(rest)
    spinning = modal_analysis(Linearization(model, about="spin", spin=2.0, spin_axis=(0, 0, 1)).at(outputs=False))
    assert len(spinning.rigid) == rigid_spinning
    assert mode_count(spinning) == rigid_at_rest
    frequencies = sorted(m.omega for m in spinning.modes if m.kind == "oscillatory")
    euler = 2.0 * np.sqrt((2.5 - 1.0) * (2.5 - 2.0) / (1.0 * 2.0))      # the classical wobble
    assert frequencies[0] == pytest.approx(euler, rel=1e-9)
    assert frequencies[1:] == pytest.approx([2.0] * (len(frequencies) - 1), rel=1e-9)
    along = [2] if joint == "spherical" else [2, 5]          # rz (and sz): about and along the spin axis
    for mode in spinning.rigid:
        np.testing.assert_allclose(np.delete(mode.shape, along), 0.0, atol=1e-9)


SPACECRAFT = """
name = "bus-with-panels"
dimensions = 3

[bodies.bus]
mass = 20.0
inertia = [2.0, 2.0, 3.0]
points = { left = [0, -0.5, 0], right = [0, 0.5, 0] }

[beams.left]
L = 1.0
rho = 0.5
EI_y = 4.0
EI_z = 6.0
GJ = 2.0
rho_Ip = 0.005
n_modes_y = 1
n_modes_z = 1
n_torsion = 1

[beams.right]
L = 1.0
rho = 0.5
EI_y = 4.0
EI_z = 6.0
GJ = 2.0
rho_Ip = 0.005
n_modes_y = 1
n_modes_z = 1
n_torsion = 1

[joints.float]
type = "free"
parent = "ground"
parent_position = [0, 0, 0]
child = "bus"

[joints.left_root]
type = "weld"
parent = "bus"
parent_point = "left"
child = "left"
orientation = { axis = [0, 0, 1], angle = -1.5707963267948966 }

[joints.right_root]
type = "weld"
parent = "bus"
parent_point = "right"
child = "right"
orientation = { axis = [0, 0, 1], angle = 1.5707963267948966 }
"""


@pytest.mark.slow
def test_free_spacecraft_with_flexible_panels_has_six_rigid_body_modes_at_rest_and_two_spinning():
    """A free bus with two panels (bending in two planes and torsion): 6 rigid-body modes at rest and
    the panels' modes; spinning freely about the axis normal to the panels (z), the shift along z and
    the turn about it only, the panels' modes labelled flap and lag."""
    model = loads_model(SPACECRAFT)
    rest = modal_analysis(Linearization(model, about="rest").at(outputs=False))
    n = rest.linear.n
    assert n == 12 and len(rest.rigid) == 6 and mode_count(rest) == n
    spinning = modal_analysis(Linearization(model, about="spin", spin=1.5, spin_axis=(0, 0, 1)).at(outputs=False))
    assert len(spinning.rigid) == 2 and mode_count(spinning) == n
    motions = [m.motion for m in spinning.modes if m.kind == "oscillatory"]
    for kind in ("flap", "lag", "torsion"):     # symmetric and antisymmetric: both panels in each mode
        assert motions.count(kind) == 2, motions
