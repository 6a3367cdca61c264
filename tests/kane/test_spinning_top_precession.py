"""A symmetric top on a spherical joint, started in steady precession, precesses uniformly at constant
tilt (the top's classical steady solution: ``m g h = Omega (I3 w3 - I1 Omega cos(theta))``, I1 the
transverse moment of inertia about the pivot, w3 the angular velocity about the symmetry axis)."""

import math

import numpy as np
import pytest

import flexkane
from flexkane.model import loads_model

M, H, I1, I3, G = 0.8, 0.07, 0.012, 0.02, 9.81
THETA, W3 = 0.5, 60.0        # tilt of the symmetry axis from the vertical [rad], spin about it [rad/s]
I1P = I1 + M * H ** 2        # transverse moment of inertia about the pivot [kg m^2]
# slow steady precession rate [rad/s]
OMEGA = (I3 * W3 - math.sqrt((I3 * W3) ** 2 - 4 * I1P * math.cos(THETA) * M * G * H)) / (2 * I1P * math.cos(THETA))

TOP = f"""
name = "top"
dimensions = 3

[bodies.top]
mass = {M}
inertia = [{I1}, {I1}, {I3}]
points = {{ tip = [0, 0, {-H}] }}

[joints.pivot]
type = "spherical"
parent = "ground"
child = "top"
child_point = "tip"

[gravity]
g = {G}
direction = [0, 0, -1]

[initial]
q_pivot = {{ axis = [1, 0, 0], angle = {THETA} }}
u_pivot_wx = 0.0
u_pivot_wy = {OMEGA * math.sin(THETA)}
u_pivot_wz = {W3}
"""


@pytest.mark.slow
def test_top_in_steady_precession_keeps_its_tilt_and_precesses_at_the_predicted_rate():
    model = loads_model(TOP)
    res = flexkane.simulate(flexkane.compile_model(flexkane.derive(model, cache=False)), t_end=3.0, dt_out=0.01,
                            rtol=1e-12, atol=1e-12)
    x, y, z = (res.outputs[f"{a}_top"] for a in "xyz")
    assert np.abs(z - H * math.cos(THETA)).max() <= 1e-8            # no nutation
    angle = np.unwrap(np.arctan2(y, x))
    assert np.abs(angle - angle[0] - OMEGA * res.t).max() <= 1e-7 * OMEGA * res.t[-1]
