"""Rigid spatial chains: flexkane's u' equal an independent sympy.physics.mechanics derivation.

The chains (spatial_models.py) are built twice from one description: as flexkane models derived by
the spatial engine (composite bodies, named intermediates), and with ``KanesMethod``
(kanes_method_reference.py, frames oriented by quaternions and axis rotations, velocities by the
two-point formulas). Their accelerations agree at random states to 1e-10. Every joint type is
covered: revolute, spherical, free, universal, prismatic, planar and cylindrical, with constant
orientations on both sides, joint springs and dampers, actuator torques and loads in local and
ground axes (the longer derivations of the reference are marked slow).
"""

import numpy as np
import pytest

import flexkane
from kanes_method_reference import kanes_method_rhs, random_state
from spatial_models import (APPLIED, FREE_UNIVERSAL_PRISMATIC, PLANAR_CYLINDRICAL_REVOLUTE,
                            SPHERICAL_DOUBLE_PENDULUM, SPINNING_TOP, THREE_JOINT_ARM, accelerations, flexkane_model)

CHAINS = {
    "spinning_top": SPINNING_TOP,
    "three_joint_arm": THREE_JOINT_ARM,
    "spherical_double_pendulum": pytest.param(SPHERICAL_DOUBLE_PENDULUM, marks=pytest.mark.slow),
    "free_universal_prismatic": pytest.param(FREE_UNIVERSAL_PRISMATIC, marks=pytest.mark.slow),
}


@pytest.mark.parametrize("description", CHAINS.values(), ids=CHAINS.keys())
def test_rigid_spatial_chain_accelerations_equal_kanes_method(description):
    reference, q_names, u_names = kanes_method_rhs(*description, gravity=(0.0, 0.0, -9.81))
    eom = flexkane.derive(flexkane_model(description), cache=False)
    assert [q.name for q in eom.q] == q_names and [u.name for u in eom.u] == u_names
    ours = accelerations(eom)
    rng = np.random.default_rng(17)
    for _ in range(4):
        q, u = random_state(q_names, u_names, rng)
        expected = reference(q, u)
        assert np.abs(ours(q, u) - expected).max() <= 1e-10 * max(1.0, np.abs(expected).max())


@pytest.mark.slow
def test_planar_cylindrical_and_revolute_joints_with_springs_and_loads_equal_kanes_method():
    reference, q_names, u_names = kanes_method_rhs(*PLANAR_CYLINDRICAL_REVOLUTE, gravity=(0.0, 0.0, -9.81),
                                                   applied=APPLIED)
    eom = flexkane.derive(flexkane_model(PLANAR_CYLINDRICAL_REVOLUTE, applied=APPLIED), cache=False)
    assert [q.name for q in eom.q] == q_names and [u.name for u in eom.u] == u_names
    ours = accelerations(eom)
    rng = np.random.default_rng(11)
    for _ in range(4):
        q, u = random_state(q_names, u_names, rng)
        expected = reference(q, u)
        assert np.abs(ours(q, u) - expected).max() <= 1e-10 * max(1.0, np.abs(expected).max())
