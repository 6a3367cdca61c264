"""A joint may carry the name of the beam it carries (the slider-crank's joint ``rod`` and beam
``rod``): the spatial engine tells the joint's coordinates from the beam's by their roles, so the
joint's speed turns the whole beam (its inertia enters), and the chain equals the planar engine's.
"""

import numpy as np

import flexkane
from flexkane.model import loads_model
from flexkane.model.as_spatial import as_spatial
from spatial_models import accelerations

ARM = """
name = "arm-named-like-its-joint"
[beams.arm]
L = 0.8
rho = 1.5
EI = 4.0
n_modes = 2
[joints.arm]
type = "revolute"
parent = "ground"
child = "arm"
[gravity]
g = 9.81
direction = [0, -1]
"""


def test_a_joint_named_like_its_beam_turns_the_beam_in_the_spatial_engine():
    planar = loads_model(ARM)
    eom2, eom3 = flexkane.derive(planar, cache=False), flexkane.derive(as_spatial(planar), cache=False)
    assert [u.name for u in eom3.u] == ["u_arm", "u_arm_y1", "u_arm_y2"]
    a2, a3 = accelerations(eom2), accelerations(eom3)
    rng = np.random.default_rng(11)
    for _ in range(3):
        q, u = rng.uniform(-0.5, 0.5, 3) * [4, 0.05, 0.01], rng.uniform(-1.0, 1.0, 3)
        expected = a2(q, u)
        assert np.abs(a3(q, u) - expected).max() <= 1e-10 * max(1.0, np.abs(expected).max())
