"""A beam with EI_y = EI_z spinning about its own axis keeps its bending frequencies.

In the frame that spins with the beam at Omega about its axis, v and w obey
``rho (v_tt - 2 Omega w_t - Omega^2 v) + EI v'''' = 0`` and ``rho (w_tt + 2 Omega v_t - Omega^2 w)
+ EI w'''' = 0``; with ``v + i w = eta e^{-i Omega t}`` these are ``rho eta_tt + EI eta'''' = 0``:
seen from the ground, the bending frequencies are the beam's at rest, and from the spinning frame
(the linearization about the steady spin) each appears as the pair ``|omega_k - Omega|`` and
``omega_k + Omega`` (backward and forward whirl), undamped.
"""

import numpy as np
import pytest

from flexkane.analysis import campbell_diagram
from flexkane.model import loads_model

LAMBDA = np.array([1.8751040687119611, 4.6940911329741745])   # clamped-free roots, eq. 8.4
L, RHO, EI = 1.5, 0.9, 12.0

SHAFT = f"""
dimensions = 3
name = "spinning-shaft"

[beams.shaft]
L = {L}
rho = {RHO}
EI_y = {EI}
EI_z = {EI}
n_modes_y = 2
n_modes_z = 2
principal_angle = 0.5
geometric_stiffening = true

[joints.spindle]
type = "revolute"
parent = "ground"
child = "shaft"
axis = [1, 0, 0]
orientation = {{ axis = [0, 1, 0], angle = -1.0 }}
"""


def test_beam_spinning_about_its_own_axis_keeps_its_bending_frequencies():
    spins = np.array([4.0, 9.0])
    diagram = campbell_diagram(loads_model(SHAFT), spins, hub="spindle")
    omega = LAMBDA ** 2 * np.sqrt(EI / (RHO * L ** 4))
    assert omega[0] < spins[-1] < omega[1]           # the first whirl pair crosses zero
    for row, growth, Omega in zip(diagram.frequencies, diagram.growth_rates, spins):
        expected = np.sort(np.concatenate([np.abs(omega - Omega), omega + Omega]))
        np.testing.assert_allclose(np.sort(row), expected, rtol=1e-7)
        assert np.max(np.abs(growth)) <= 1e-8 * omega[1]
