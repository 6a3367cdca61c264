"""Geometric stiffening (issue 7): the spin-up manoeuvre of Kane, Ryan and Banerjee (1987).

The chapter's linear formulation lets the tip deflection of a beam on a spinning hub grow without bound
once the spin passes the first bending frequency (about 3.80 rad/s here); keeping the foreshortening of
the beam axis in the kinematics stiffens the beam and the deflection stays small.
"""

import numpy as np
import pytest
from scipy.integrate import cumulative_trapezoid

import flexkane
from flexkane.model import Joint, RigidBody


def run(model, t_end=20.0, dt_out=0.01, rtol=1e-9, atol=1e-11):
    compiled = flexkane.compile_model(flexkane.derive(model))
    return flexkane.simulate(compiled, t_end=t_end, dt_out=dt_out, rtol=rtol, atol=atol, model=model)


@pytest.fixture(scope="module")
def stiffened():
    return run(flexkane.builtin_model("spin-up"))


def test_first_bending_frequency_of_the_spin_up_beam_is_about_3_8_rad_s():
    from flexkane.modes import get_family
    p1 = get_family("clamped-free").frequencies(1, 10.0, 1.4e4, 1.2)[0]
    assert abs(p1 - 3.80) < 0.01


def test_linear_formulation_tip_deflection_grows_without_bound():
    res = run(flexkane.builtin_model("spin-up-linear"), rtol=1e-8, atol=1e-10, dt_out=0.05)
    tip = np.abs(res["tip_beam"])
    at_T = tip[res.t <= 15.0].max()
    assert tip[-1] > 1e3 * max(at_T, 1.0)          # exponential growth after the spin passes p1
    assert tip[-1] > 1e3                           # metres: no physical beam does this


def test_stiffened_tip_deflection_stays_below_a_metre_and_settles(stiffened):
    tip = np.abs(stiffened["tip_beam"])
    assert 0.05 < tip.max() < 1.0
    assert tip[stiffened.t >= 17.0].max() < 0.02


def test_driver_power_equals_rate_of_kinetic_plus_strain_energy(stiffened):
    e = stiffened["kinetic"] + stiffened["strain"]
    # the hub's speed is prescribed: the power supplied is effort_hub * theta'(t)
    work = cumulative_trapezoid(stiffened["power_nonconservative"], stiffened.t, initial=0.0)
    assert np.abs(stiffened["effort_hub"]).max() > 1.0
    assert np.abs(e - e[0] - work).max() < 1e-5 * np.abs(e).max()


def test_tip_deflection_converges_as_modes_are_added():
    peaks = []
    for n in (2, 3, 4):
        res = run(flexkane.builtin_model("spin-up").with_modes(n), t_end=15.0, dt_out=0.02)
        peaks.append(np.abs(res["tip_beam"]).max())
    assert abs(peaks[2] - peaks[1]) < abs(peaks[1] - peaks[0]) + 1e-4
    assert abs(peaks[2] - peaks[1]) < 0.02 * peaks[2]


def test_stiffening_works_with_a_hub_offset_and_a_tip_mass():
    model = flexkane.builtin_model("spin-up").with_modes(3)
    model.parameters.update({"r": 0.5, "m_h": 5.0, "J_h": 1.0, "m_tip": 2.0})
    model.bodies["hub"] = RigidBody("hub", "m_h", "J_h", {"clamp": ("r", 0)})
    model.bodies["tip"] = RigidBody("tip", "m_tip", 0.01)
    model.joints["hub"].child = "hub"
    model.joints["clamp"] = Joint("clamp", "weld", "hub", "beam", parent_point="clamp")
    model.joints["tip"] = Joint("tip", "weld", "beam", "tip", station="L")
    model.validate()
    res = run(model, t_end=20.0, dt_out=0.01)
    tip = np.abs(res["tip_beam"])
    assert tip.max() < 1.0
    e = res["kinetic"] + res["strain"]
    work = cumulative_trapezoid(res["power_nonconservative"], res.t, initial=0.0)
    assert np.abs(e - e[0] - work).max() < 1e-5 * np.abs(e).max()
