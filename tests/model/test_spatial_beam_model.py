"""Spatial beams in model files (dimensions = 3): fields, coordinate names, round trip, as_spatial."""

from flexkane.builtin import builtin_model
from flexkane.model import as_spatial, dumps_model, loads_model
from flexkane.model.coordinates import coordinate_names
from flexkane.model.parts import ShapeSpec

BLADE = """
dimensions = 3
name = "blade"

[beams.blade]
L = 2.0
rho = 0.5
EI_y = 10.0
EI_z = 40.0
GJ = 6.0
rho_Ip = 0.002
EA = 1e5
n_modes_y = 2
n_modes_z = 3
n_torsion = 1
n_axial = 1
shape_z = { family = "clamped-free", roots = [1.875, 4.694, 7.855] }
principal_angle = 0.1
geometric_stiffening = true

[joints.hub]
type = "revolute"
parent = "ground"
child = "blade"
axis = [0, 0, 1]

[initial]
q_blade_z1 = 0.01
u_blade_t1 = 0.5
"""


def test_spatial_beam_fields_and_coordinate_names():
    model = loads_model(BLADE)
    beam = model.beams["blade"]
    assert (beam.EI_y, beam.EI_z, beam.GJ, beam.rho_Ip, beam.EA) == (10.0, 40.0, 6.0, 0.002, 1e5)
    assert (beam.n_modes_y, beam.n_modes_z, beam.n_torsion, beam.n_axial) == (2, 3, 1, 1)
    assert beam.shape_y == ShapeSpec("clamped-free") and beam.shape_z.roots == [1.875, 4.694, 7.855]
    assert beam.torsion_shape == ShapeSpec("torsion-clamped-free")
    assert beam.axial_shape == ShapeSpec("axial-fixed-free")
    names = [(c.q, c.u, c.role, c.index) for c in coordinate_names(model) if c.owner == "blade"]
    assert names == [("q_blade_y1", "u_blade_y1", "mode_y", 1), ("q_blade_y2", "u_blade_y2", "mode_y", 2),
                     ("q_blade_z1", "u_blade_z1", "mode_z", 1), ("q_blade_z2", "u_blade_z2", "mode_z", 2),
                     ("q_blade_z3", "u_blade_z3", "mode_z", 3), ("q_blade_t1", "u_blade_t1", "torsion", 1),
                     ("s_blade_1", "v_blade_1", "axial", 1)]


def test_spatial_beam_model_file_round_trip():
    model = loads_model(BLADE)
    assert loads_model(dumps_model(model)) == model


def test_as_spatial_maps_a_planar_beam_to_one_bending_in_its_frames_x_y_plane():
    planar = builtin_model("pendulum-beam").with_values({"q_rod_2": 0.01})
    beam = planar.beams["rod"]
    spatial = as_spatial(planar).beams["rod"]
    assert spatial.EI_z == beam.EI and spatial.n_modes_y == beam.n_modes and spatial.shape_y == beam.shape
    assert spatial.n_modes_z == 0 and spatial.n_torsion == 0 and spatial.EI is None
    assert as_spatial(planar).initial["q_rod_y2"] == 0.01 and "q_rod_2" not in as_spatial(planar).initial


def test_modes_text_names_the_rayleigh_option_of_spatial_beams_as_of_planar_ones():
    planar = builtin_model("pendulum-beam")
    assert not planar.beams["rod"].rayleigh and "Rayleigh" not in planar.beams["rod"].modes_text()
    rayleigh = planar.with_values({"beams.rod.rotary_inertia": 1e-4}).beams["rod"]
    assert rayleigh.rayleigh and rayleigh.modes_text().endswith(", Rayleigh")
    spatial = loads_model(BLADE)
    beam = spatial.beams["blade"]
    assert beam.modes_text() == "2 y clamped-free + 3 z clamped-free + 1 torsion + 1 axial"
    assert not beam.rayleigh
    both = loads_model(BLADE.replace("geometric_stiffening = true", "geometric_stiffening = true\n"
                                     "rho_Iy = 1e-4\nrho_Iz = 2e-4")).beams["blade"]
    assert both.rayleigh and both.modes_text().endswith("1 axial, Rayleigh")
    only_v = loads_model(BLADE.replace("geometric_stiffening = true", "geometric_stiffening = true\n"
                                       "rho_Iz = 2e-4\nrho_Iy = 0")).beams["blade"]
    assert only_v.rayleigh_planes() == ["y"] and only_v.modes_text().endswith(", Rayleigh in y")
    as_3d = as_spatial(planar.with_values({"beams.rod.rotary_inertia": 1e-4})).beams["rod"]
    assert as_3d.modes_text().endswith(", Rayleigh in y")   # the planar beam's sections turn about z
