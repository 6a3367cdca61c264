"""Names of the constants generated for spatial beams: every modal constant of a spatial beam is
recognized as generated (``E_y1``, ``G_y1_z1``, ``H_z11``, ``Kt_11``, ``Irz_B`` ...), so a
parameter named like one is refused and printed equations stay readable."""

import pytest

import flexkane
from flexkane.errors import ModelError
from flexkane.model import loads_model
from flexkane.model.constant_names import generated_constant

BLADE = """
dimensions = 3
name = "every-spatial-constant"

[parameters]
{parameter} = 2.0

[bodies.hub]
mass = 1.0
inertia = [0.1, 0.1, 0.2]
points = {{ root = [0.1, 0, 0] }}

[beams.blade]
L = 1.0
rho = 0.8
EI_y = 20.0
EI_z = 30.0
GJ = 5.0
rho_Ip = 0.01
rho_Iy = 0.002
rho_Iz = 0.003
EA = 900.0
n_modes_y = 1
n_modes_z = 1
n_torsion = 1
n_axial = 1
geometric_stiffening = true

[joints.spin]
type = "revolute"
parent = "ground"
child = "hub"
axis = [0, 0, 1]

[joints.clamp]
type = "weld"
parent = "hub"
parent_point = "root"
child = "blade"
"""


def test_every_modal_constant_of_a_spatial_beam_is_a_generated_name():
    eom = flexkane.derive(loads_model(BLADE.format(parameter="c")), cache=False)
    names = {s.name for s in eom.kinematics.constants["blade"].used if "(" not in s.name}   # not the stations
    assert {"E_y1", "G_y1_z1", "H_z11", "HA_11", "DD_y11_z11", "Dphi_y11_z1", "Kt_11", "Gt_11", "Et_1",
            "Er_y1", "Gr_z1_z1", "Ip_blade", "Iry_blade", "Irz_blade", "m_blade"} <= names
    unknown = {name for name in names if generated_constant(name, "blade", "") is None}
    assert not unknown


@pytest.mark.parametrize("name", ["H_y11", "Kt_11", "Gr_z1_z2", "Irz_blade", "DD_y11_z22"])
def test_a_parameter_named_like_a_spatial_beam_constant_is_refused(name):
    with pytest.raises(ModelError, match=rf"parameters\.{name}.*rename the parameter"):
        loads_model(BLADE.format(parameter=name))


def test_names_that_only_look_alike_stay_parameters():
    for name in ("H_x11", "Kt_y", "Iry_hub", "Gt_11a"):
        assert loads_model(BLADE.format(parameter=name)).parameters[name] == 2.0
