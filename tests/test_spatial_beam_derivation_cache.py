"""The derivation cache of spatial beams: their numbers (EI_y, EI_z, GJ, rho_Ip, rho_Iy, rho_Iz,
principal_angle, damping ratios, EA) and the 3D paths (inertia tensor entries, point and position
components, orientation angles) do not change the structure, so a sweep over them derives once; the
equations taken from the cache take the numbers of the model given."""

import numpy as np
import pytest

import flexkane
import flexkane.kane
from flexkane.derivation_cache import cached_derive, structure_signature
from flexkane.model import loads_model

ARM = """
dimensions = 3
name = "spatial-beam-sweep"

[bodies.hub]
mass = 2.0
inertia = [[0.3, 0.01, 0.0], [0.01, 0.2, 0.0], [0.0, 0.0, {Izz}]]
points = {{ root = [0.1, 0.0, {z}] }}

[beams.b]
L = 1.0
rho = 0.8
EI_y = {EI_y}
EI_z = 30.0
GJ = {GJ}
rho_Ip = {rho_Ip}
rho_Iy = {rho_Iy}
rho_Iz = 0.003
EA = 900.0
n_modes_y = 1
n_modes_z = 1
n_torsion = 1
n_axial = 1
principal_angle = {beta}
damping_y = {zeta}

[joints.spin]
type = "revolute"
parent = "ground"
child = "hub"
parent_position = [0, 0, {h}]
axis = [0, 0, 1]
orientation = {{ sequence = "zyx", angles = [0.1, {pitch}, 0.0] }}

[joints.clamp]
type = "weld"
parent = "hub"
parent_point = "root"
child = "b"
orientation = {{ axis = [0, 1, 0], angle = {angle} }}
"""

BASE = dict(Izz=0.25, z=0.05, EI_y=20.0, GJ=5.0, rho_Ip=0.01, rho_Iy=0.002, beta=0.3, zeta=0.02, h=0.5,
            pitch=0.2, angle=0.1)
OTHER = dict(Izz=0.35, z=-0.04, EI_y=25.0, GJ=6.5, rho_Ip=0.02, rho_Iy=0.004, beta=0.6, zeta=0.05, h=0.7,
             pitch=-0.3, angle=0.25)


@pytest.fixture
def count_derivations(monkeypatch):
    calls = []
    original = flexkane.kane.derive

    def counting(model):
        calls.append(model.name)
        return original(model)

    monkeypatch.setattr(flexkane.kane, "derive", counting)
    return calls


def test_spatial_beam_numbers_and_3d_paths_reuse_one_derivation(tmp_path, count_derivations):
    base, other = loads_model(ARM.format(**BASE)), loads_model(ARM.format(**OTHER))
    assert structure_signature(other) == structure_signature(base)
    cached_derive(base, tmp_path)
    cached = cached_derive(other, tmp_path)
    assert len(count_derivations) == 1                     # the second model came from the cache
    # its numbers are the other model's: each changed value, and the modal constants it scales
    new, old = (dict(zip((s.name for s in cached.constants), cached.parameter_vector(m))) for m in (other, base))
    for name, value in (("beta_b", 0.6), ("zeta_b_y1", 0.05), ("Iry_b", 0.004), ("Ip_b", 0.02),
                        ("hub_root_z", -0.04), ("p_spin_z", 0.7), ("I_hub_zz", 0.35), ("Op_spin_2", -0.3),
                        ("Op_clamp_angle", 0.25)):
        assert new[name] == pytest.approx(value, rel=1e-15), name
    for name, ratio in (("H_z11", 25.0 / 20.0), ("Kt_11", 6.5 / 5.0), ("Gr_z1_z1", 2.0), ("Gt_11", 2.0)):
        assert new[name] == pytest.approx(ratio * old[name], rel=1e-13), name
    changed = {name for name in new if new[name] != old[name]}
    assert len(changed) >= 14, sorted(changed)
    # a literal zero (no turning sections about y_p, no damping) leaves terms out: structure
    for key in ("rho_Iy", "zeta", "beta"):
        assert structure_signature(loads_model(ARM.format(**{**BASE, key: 0}))) != structure_signature(base)
