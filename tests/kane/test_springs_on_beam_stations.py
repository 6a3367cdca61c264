"""Springs and dampers attached to beam stations follow the deflected beam (issue 14, item 7)."""

import math

import numpy as np
import pytest
import sympy as sp

import flexkane
from flexkane.analysis import linearize, modal_analysis
from flexkane.modes import get_family

TEXT = """
name = "cantilever-on-a-spring"
[parameters]
L = 1.0
EI = 2.0
rho = 0.5
[beams.beam]
L = "L"
EI = "EI"
rho = "rho"
n_modes = 1
[joints.clamp]
type = "weld"
parent = "ground"
child = "beam"
[springs.support]
body_a = "ground"
position_a = [{s}, -0.3]
body_b = "beam"
station_b = {s}
rest_length = 0.3
stiffness = {k}
damping = {c}
"""


@pytest.mark.parametrize("s", [0.6, 1.0])
def test_spring_and_damper_at_a_station_act_on_the_deflection_there(s):
    """One mode: w^2 = (H_11 + k Phi_1(s)^2) / G_11 and 2 zeta w G_11 = c Phi_1(s)^2 (Rayleigh)."""
    k, c = 7.0, 0.05
    model = flexkane.loads_model(TEXT.format(s=s, k=k, c=c))
    modal = modal_analysis(linearize(model, about="rest"))
    lam = get_family("clamped-free").roots(1)[0]
    phi_s = get_family("clamped-free").phi(np.array([s / 1.0]), 1)[0, 0]
    G, H = 0.5 * 1.0, 2.0 * lam ** 4 / 1.0 ** 3
    w = math.sqrt((H + k * phi_s ** 2) / G)
    zeta = c * phi_s ** 2 / (2 * w * G)
    (mode,) = modal.elastic
    assert mode.omega == pytest.approx(w, rel=1e-9)
    assert mode.damping_ratio == pytest.approx(zeta, rel=1e-9)


def test_spring_energy_follows_the_deflected_station():
    """The spring's energy is 1/2 k (l - l0)^2 with l from the deflected point of the station."""
    model = flexkane.loads_model(TEXT.format(s=0.6, k=7.0, c=0.0))
    eom = flexkane.derive(model)
    values = eom.constant_values(model)
    q = 0.01
    energy = float(sp.sympify(eom.outputs["potential_springs"]).xreplace(values).xreplace({eom.q[0]: q}))
    phi = get_family("clamped-free").phi(np.array([0.6]), 1, 0)[0, 0]
    # the station point sits at (x - foreshortening, Phi(s) q): without geometric stiffening, at (s, Phi q)
    length = 0.3 + phi * q
    assert energy == pytest.approx(0.5 * 7.0 * (length - 0.3) ** 2, rel=1e-12)
