"""Physics of the flexible spatial built-in examples (issue 17 item 6 and its physics checks).

* ``spacecraft-flexible-slew`` without its slew torque, tumbling with its panels bent and twisted and
  its bus moving so that the total momentum is zero: the angular momentum vector and the energy
  (kinetic + strain) stay constant to the solver's tolerance while the panels vibrate, and the
  centre of mass of the whole system stays at rest.
* ``rotor-blade`` at its steady spin: the steady coning deflection (the flap of the blade in the
  rotating frame) equals an independent Rayleigh-Ritz solution from the potential energy in the
  rotating frame (bending strain, gravity, centrifugal potential with the foreshortening, the
  lift), for the model's precone and for none; the precone, near the balance of lift, weight and
  centrifugal force, makes the coning deflection several times smaller; the first flap frequency
  rises with the spin as that energy's stiffness predicts.
* ``robot-arm-3d-flexible``: power balance, the work of the joint torques and dampers equals the
  change of kinetic, strain, gravity and servo-spring energy, and that work equals the integral of
  the torques' and dampers' power computed from the run's speeds.
"""

from __future__ import annotations

import numpy as np
import pytest

import flexkane
from flexkane.modes import get_family


def _compiled(name):
    model = flexkane.builtin_model(name)
    eom = flexkane.derive(model)
    return model, eom, flexkane.compile_model(eom)


@pytest.fixture(scope="module")
def spacecraft():
    return _compiled("spacecraft-flexible-slew")


def test_torque_free_flexible_spacecraft_conserves_momentum_and_energy_and_its_centre_of_mass_rests(spacecraft):
    model, _, compiled = spacecraft
    model.parameters["T0"] = 0.0
    model.initial.update({"u_float_wx": 0.05, "u_float_wy": -0.03, "u_float_wz": 0.1,
                          "q_panel_right_z1": 0.02, "q_panel_left_z1": -0.01, "q_panel_right_y1": 0.002,
                          "q_panel_left_t1": 0.02, "u_panel_right_z1": 0.05, "u_panel_left_y2": 0.001})
    # the bus's velocity that makes the total momentum zero (p is linear in the speeds, the bus
    # frame starts aligned with N and the total mass is 220 kg)
    start = flexkane.simulate(compiled, model=model, t_end=1e-3, dt_out=1e-3)
    for axis in "xyz":
        model.initial[f"u_float_v{axis}"] = -start[f"p_{axis}"][0] / 220.0
    results = flexkane.simulate(compiled, model=model, t_end=8.0, dt_out=0.05, rtol=1e-11, atol=1e-13)
    H = np.column_stack([results["H_x"], results["H_y"], results["H_z"]])
    assert np.linalg.norm(H[0]) > 1.0
    assert np.max(np.abs(H - H[0])) < 1e-8 * np.linalg.norm(H[0])
    strain, energy = results["strain"], results["energy"]
    assert np.ptp(strain) > 1e-2 * np.max(energy)                      # the panels vibrate
    assert np.max(np.abs(energy - energy[0])) < 1e-8 * np.max(energy)
    p = np.column_stack([results["p_x"], results["p_y"], results["p_z"]])
    assert np.max(np.abs(p)) < 1e-10 * 220.0
    cm = np.column_stack([results["x_cm"], results["y_cm"], results["z_cm"]])
    assert np.max(np.abs(cm - cm[0])) < 1e-9                           # [m], at rest
    assert np.ptp(results["x_bus"]) > 1e-4                             # while the bus moves
    assert np.max(np.abs(results["quaternion_norm_float"])) < 1e-9


# ---------------------------------------------------------------------------------------- rotor blade
@pytest.fixture(scope="module")
def rotor():
    return _compiled("rotor-blade")


def _steady_flap(model, eom, compiled, t=5.0):
    """The elastic coordinates where the blade is at rest in the rotating frame (u' = 0 of the blade
    speeds, all of them zero) at the steady spin, by Newton's method on the compiled equations; and
    the Jacobian there."""
    values = eom.constant_values(model)
    p = np.array([values[c] for c in eom.constants], dtype=float)
    names = list(eom.state_names)
    nq = len(eom.q)
    y = eom.initial_state(model).copy()
    elastic = [names.index(n) for n in names[:nq] if n.startswith("q_blade")]

    def residual(qe):
        z = y.copy()
        z[elastic] = qe
        return compiled.rhs(t, z, p)[nq:nq + len(elastic)]

    qe = np.zeros(len(elastic))
    for _ in range(20):
        r = residual(qe)
        J = np.column_stack([(residual(qe + h) - residual(qe - h)) / 2e-8 for h in np.eye(len(qe)) * 1e-8])
        step = np.linalg.solve(J, -r)
        qe = qe + step
        if np.max(np.abs(step)) < 1e-15:
            break
    return dict(zip([names[i] for i in elastic], qe)), J


def _rayleigh_ritz(values, modes=2):
    """Flap coordinates of the steady coning and the first flap frequency from the potential energy in
    the frame turning at Omega0 (w along the blade's z, tilted up by the precone b from the plane of
    rotation, root at the hub radius e):

        V = 1/2 int EI w''^2 + g cos b int rho w + Omega^2 sin b int rho (e + x cos b) w
            - 1/2 Omega^2 sin^2 b int rho w^2 + int (Omega^2 cos b rho (e + x cos b) - g sin b rho) s dx
            - F w(3 L / 4),   s(x) = 1/2 int_0^x w'^2,

    to second order in w (the lift a follower force normal to the section: its work is F w to
    second order), and the kinetic energy 1/2 int rho w_t^2 of the flap alone."""
    L, rho, EI, e, b = (values[k] for k in ("L", "rho", "EI_flap", "e", "precone"))
    Omega, g, F = values["Omega0"], 9.81, values["F_lift"]
    family = get_family("clamped-free")
    xi, w = np.polynomial.legendre.leggauss(80)
    xi, w = (xi + 1) / 2, w / 2 * L
    x = xi * L
    phi = family.phi(xi, modes)
    d1 = family.phi(xi, modes, deriv=1) / L
    d2 = family.phi(xi, modes, deriv=2) / L ** 2
    # tension-like weight of the foreshortening at x: int_x^L (Omega^2 cos b rho (e + s cos b) - g sin b rho) ds
    weight = Omega ** 2 * np.cos(b) * rho * (e * (L - x) + np.cos(b) * (L ** 2 - x ** 2) / 2) - g * np.sin(b) * rho * (L - x)
    K = (EI * d2 * w) @ d2.T + (weight * d1 * w) @ d1.T - Omega ** 2 * np.sin(b) ** 2 * rho * (phi * w) @ phi.T
    M = rho * (phi * w) @ phi.T
    load = -(rho * (g * np.cos(b) + Omega ** 2 * np.sin(b) * (e + x * np.cos(b))) * phi) @ w
    load = load + F * family.phi(np.array([0.75]), modes)[:, 0]
    flap = np.sqrt(np.min(np.linalg.eigvals(np.linalg.solve(M, K)).real))
    return np.linalg.solve(K, load), flap


@pytest.mark.parametrize("precone", [None, 0.0])
def test_rotor_blade_steady_coning_equals_the_rayleigh_ritz_solution(rotor, precone):
    model, eom, compiled = rotor
    model = flexkane.builtin_model("rotor-blade")
    if precone is not None:
        model.parameters["precone"] = precone
    steady, _ = _steady_flap(model, eom, compiled)
    expected, _ = _rayleigh_ritz(model.parameters)
    found = np.array([steady["q_blade_z1"], steady["q_blade_z2"]])
    assert np.max(np.abs(found - expected)) < 2e-3 * np.max(np.abs(expected)), (found, expected)
    for name in ("q_blade_y1", "q_blade_y2", "q_blade_t1"):             # no lag, no twist
        assert abs(steady[name]) < 1e-9 * np.max(np.abs(expected))


def test_precone_reduces_the_coning_deflection_and_spin_raises_the_flap_frequency(rotor):
    _, eom, compiled = rotor
    model = flexkane.builtin_model("rotor-blade")
    tip = get_family("clamped-free").phi(np.array([1.0]), 2)[:, 0]
    deflection = {}
    precone = model.parameters["precone"]
    for value in (0.0, precone):
        model.parameters["precone"] = value
        steady, J = _steady_flap(model, eom, compiled)
        deflection[value] = tip @ [steady["q_blade_z1"], steady["q_blade_z2"]]
    assert deflection[0.0] > 0.01                                       # bent up by the lift [m]
    assert abs(deflection[precone]) < 0.25 * deflection[0.0]
    # first flap frequency spinning (the model's, from the Jacobian of its equations at the steady
    # coning: the lowest of the blade's modes) against the energy's stiffness, and at rest
    values = dict(model.parameters)
    spinning = _rayleigh_ritz(values)[1]
    assert np.sqrt(np.min(np.linalg.eigvals(-J).real)) == pytest.approx(spinning, rel=1e-3)
    still = _rayleigh_ritz(dict(values, Omega0=0.0, F_lift=0.0, precone=0.0))[1]
    assert spinning > 1.1 * still
    assert still == pytest.approx(1.8751040687 ** 2 * np.sqrt(values["EI_flap"] / (values["rho"] * values["L"] ** 4)),
                                  rel=1e-6)


# ---------------------------------------------------------------------------------------- flexible arm
def test_flexible_arm_power_balance():
    model, _, compiled = _compiled("robot-arm-3d-flexible")
    results = flexkane.simulate(compiled, model=model, t_end=1.0, dt_out=0.001, rtol=1e-10, atol=1e-12)
    energy, work = results["energy"], results["work"]
    assert np.max(np.abs(work)) > 1.0                                   # the torques do work [J]
    assert np.ptp(results["strain"]) > 1e-3                             # the links bend and twist [J]
    balance = energy - energy[0] - work
    assert np.max(np.abs(balance)) < 1e-8 * np.max(np.abs(results["kinetic"]) + np.abs(energy))
    # the work from the run's speeds: joint torques and dampers (parameters of the model)
    v = model.parameters
    t = results.t
    power = (np.where(t < v["t1"], v["T_waist"] * np.sin(2 * np.pi * t / v["t1"]), 0) * results["u_waist"]
             + (v["T_sh"] + v["dT_sh"] * np.where(t < v["t1"], np.sin(np.pi * t / v["t1"]), 0)) * results["u_shoulder"]
             - v["c_sh"] * results["u_shoulder"] ** 2
             + v["T_el"] * results["u_elbow"] - v["c_el"] * results["u_elbow"] ** 2)
    trapezoid = np.concatenate([[0.0], np.cumsum((power[1:] + power[:-1]) / 2 * np.diff(t))])
    assert np.max(np.abs(trapezoid - work)) < 1e-4 * np.max(np.abs(work))
