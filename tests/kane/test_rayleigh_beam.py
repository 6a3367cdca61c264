"""Rayleigh beams: the rotary inertia of the sections (``rotary_inertia = rho I`` [kg m]).

The oracle is the exact frequency equation of the clamped-free Rayleigh beam, derived here from its
equation of motion and boundary conditions (Hamilton's principle with the kinetic energy
``1/2 int (rho w_t^2 + rho_I w_xt^2) dx`` and the strain energy ``1/2 int EI w_xx^2 dx``):

    EI w'''' + rho w_tt - rho_I w_xxtt = 0,
    w(0) = w'(0) = 0,   EI w''(L) = 0,   EI w'''(L) - rho_I w_xtt(L) = 0.

With ``w = W(x) e^{i p t}`` and ``EI = rho = L = 1``, ``r2 = rho_I``, ``W = C1 cosh(a x) + C2 sinh(a x)
+ C3 cos(b x) + C4 sin(b x)`` where ``a^2, -b^2`` are the roots of ``s^4 + r2 p^2 s^2 - p^2 = 0``
(so ``b^2 - a^2 = r2 p^2``). The clamped root gives ``C3 = -C1``, ``C4 = -a C2 / b``; the two tip
conditions then have a non-trivial solution when

    (a^2 Ch + b^2 c)(b^2 Ch + a^2 c) - b (a^2 Sh + a b s)(b Sh - a s) = 0,

``Ch, Sh = cosh a, sinh a``, ``c, s = cos b, sin b``. For ``r2 = 0`` (``a = b = lambda``) it is
``2 lambda^4 (1 + cos lambda cosh lambda) = 0``, the Euler-Bernoulli cantilever (eq. 8.6).
"""

import numpy as np
import pytest
import sympy as sp
from scipy.optimize import brentq

import flexkane
from flexkane import Model
from flexkane.errors import ModelError
from flexkane.analysis import linearize, modal_analysis
from flexkane.model.parts import Beam, Joint, RigidBody


def rayleigh_cantilever_determinant(p, r2):
    """The frequency determinant above divided by cosh(a)^2 (O(1) for every p)."""
    root = np.sqrt(r2 ** 2 * p ** 4 + 4.0 * p ** 2)
    a = np.sqrt((root - r2 * p ** 2) / 2.0)
    b = np.sqrt((root + r2 * p ** 2) / 2.0)
    Ch, Sh = 1.0, np.tanh(a)
    c, s = np.cos(b) / np.cosh(a), np.sin(b) / np.cosh(a)
    return (a * a * Ch + b * b * c) * (b * b * Ch + a * a * c) - b * (a * a * Sh + a * b * s) * (b * Sh - a * s)


def rayleigh_cantilever_frequencies(r2, count):
    """First ``count`` natural frequencies [rad/s] (EI = rho = L = 1), by bracketing and brentq."""
    grid = np.linspace(0.5, 250.0, 100_000)
    values = rayleigh_cantilever_determinant(grid, r2)
    roots = [brentq(rayleigh_cantilever_determinant, lo, hi, args=(r2,), xtol=1e-14, rtol=1e-15)
             for lo, hi, f0, f1 in zip(grid[:-1], grid[1:], values[:-1], values[1:]) if f0 * f1 < 0]
    return np.array(roots[:count])


def cantilever(n_modes, rotary_inertia):
    model = Model(name="rayleigh-cantilever", parameters={"L": 1.0, "EI": 1.0, "rho": 1.0, "rI": 0.0025})
    model.beams["B"] = Beam(name="B", L="L", EI="EI", rho="rho", n_modes=n_modes,
                            rotary_inertia=rotary_inertia)
    model.joints["clamp"] = Joint(name="clamp", type="weld", parent="ground", child="B")
    return model


def test_frequency_equation_without_rotary_inertia_is_the_euler_bernoulli_cantilevers():
    lam = np.array([1.8751040687119611, 4.6940911329741746, 7.8547574382376126, 10.995540734875467])
    np.testing.assert_allclose(rayleigh_cantilever_frequencies(0.0, 4), lam ** 2, rtol=1e-12)


def test_rayleigh_cantilever_frequencies_converge_to_the_exact_roots_from_above():
    r2 = 0.0025                                   # radius of gyration of the section: L / 20
    exact = rayleigh_cantilever_frequencies(r2, 3)
    euler_bernoulli = rayleigh_cantilever_frequencies(0.0, 3)
    assert np.all(exact < euler_bernoulli)
    errors = []
    for n in (4, 8, 12):
        modal = modal_analysis(linearize(cantilever(n, "rI")))
        assert not modal.rigid
        p = modal.frequencies[:3]
        assert np.all(p < euler_bernoulli)        # rotary inertia lowers every frequency
        errors.append((p - exact) / exact)
    errors = np.array(errors)
    assert np.all(errors > -1e-12)                # Rayleigh-Ritz bounds the exact values from above
    assert np.all(np.diff(errors, axis=0) < 0)    # and approaches them as modes are added
    assert np.max(errors[-1][:2]) < 2e-6 and errors[-1][2] < 5e-5
    # the effect is far larger than the convergence error: the third frequency drops by 8 %
    assert (euler_bernoulli[2] - exact[2]) / euler_bernoulli[2] > 0.08


def test_zero_rotary_inertia_gives_the_equations_of_a_beam_without_the_field():
    plain = flexkane.derive(cantilever(3, None), cache=False)
    zero = flexkane.derive(cantilever(3, 0), cache=False)
    assert sp.srepr(zero.mass_matrix) == sp.srepr(plain.mass_matrix)
    assert sp.srepr(zero.forcing) == sp.srepr(plain.forcing)
    assert sp.srepr(zero.outputs) == sp.srepr(plain.outputs)
    assert zero.constants == plain.constants
    rayleigh = flexkane.derive(cantilever(3, "rI"), cache=False)
    assert sp.srepr(rayleigh.mass_matrix) != sp.srepr(plain.mass_matrix)
    # int rho_I Phi_i' Phi_j' dx (mass matrix, kinetic energy), int rho_I Phi_i' dx (angular momentum)
    assert {s.name for s in rayleigh.constants} - {s.name for s in plain.constants} \
        == {"Gr_11", "Gr_12", "Gr_13", "Gr_22", "Gr_23", "Gr_33", "Er_1", "Er_2", "Er_3"}


def hub_beam(EI, rotary_inertia, *, tip=False, torque=None, J_h=0.2):
    """A hub turning freely about a fixed axis with a beam clamped to it, optionally a pendulum
    hinged at the beam's tip; no gravity."""
    model = Model(name="hub-rayleigh", parameters={"L": 1.0, "EI": EI, "rho": 1.5, "rI": 0.02, "J_h": J_h})
    model.bodies["hub"] = RigidBody(name="hub", mass=2.0, inertia="J_h")
    model.beams["B"] = Beam(name="B", L="L", EI="EI", rho="rho", n_modes=3, rotary_inertia=rotary_inertia)
    model.joints["axis"] = Joint(name="axis", type="revolute", parent="ground", child="hub", torque=torque)
    model.joints["clamp"] = Joint(name="clamp", type="weld", parent="hub", child="B")
    if tip:
        model.bodies["P"] = RigidBody(name="P", mass=0.3, inertia=0.004, points={"pin": (-0.1, 0.0)})
        model.joints["hinge"] = Joint(name="hinge", type="revolute", parent="B", station="L", child="P",
                                      child_point="pin")
    return model


def test_hub_inertia_of_a_rayleigh_beam_gains_the_sections_moment_of_inertia():
    J_h, rho, L, rI = 0.2, 1.5, 1.0, 0.02
    with_sections = linearize(hub_beam(1e6, "rI", J_h=J_h))
    without = linearize(hub_beam(1e6, None, J_h=J_h))
    assert with_sections.speeds[0] == "u_axis"
    # a rigid beam turning with the hub: J_h + int rho x^2 dx + int rho_I dx
    assert with_sections.M[0, 0] == pytest.approx(J_h + rho * L ** 3 / 3 + rI * L, rel=1e-12)
    assert without.M[0, 0] == pytest.approx(J_h + rho * L ** 3 / 3, rel=1e-12)
    # coupling of the hub with mode i gains int rho_I Phi_i' dx = rho_I Phi_i(L) (Phi_i(L) = +-2)
    tip = np.array([2.0, -2.0, 2.0])
    np.testing.assert_allclose(with_sections.M[0, 1:] - without.M[0, 1:], rI * tip, rtol=1e-9)


@pytest.mark.slow
def test_hub_with_stiff_rayleigh_beam_turns_like_a_rigid_body_with_the_sections_inertia():
    torque, t_end = 0.7, 0.5
    J_h, rho, L, rI = 0.2, 1.5, 1.0, 0.02
    model = hub_beam(1e6, "rI", torque=torque, J_h=J_h)
    results = flexkane.simulate(flexkane.compile_model(flexkane.derive(model)), t_end=t_end, dt_out=t_end / 10,
                                rtol=1e-10, atol=1e-12, method="radau")
    rigid = J_h + rho * L ** 3 / 3 + rI * L              # the sections add int rho_I dx = rho_I L
    expected = torque * results.t ** 2 / (2 * rigid)
    # the beam's vibration, excited by the sudden torque, moves the hub by ~1e-7 rad
    np.testing.assert_allclose(results["q_axis"], expected, rtol=0, atol=1e-5 * expected[-1])
    # without the sections' inertia the angle would differ by 3 %
    assert abs(torque * t_end ** 2 / (2 * (rigid - rI * L)) / expected[-1] - 1) > 0.025


def test_free_rayleigh_chain_conserves_energy_and_angular_momentum():
    model = hub_beam(6.0, "rI", tip=True)
    model.initial.update({"u_axis": 2.0, "q_B_1": 0.05, "u_B_2": -0.4, "u_hinge": 1.5})
    compiled = flexkane.compile_model(flexkane.derive(model))
    results = flexkane.simulate(compiled, t_end=2.0, dt_out=0.01, rtol=1e-11, atol=1e-13)
    assert not results.partial
    energy, h = results["energy"], results["h_o"]
    assert np.ptp(energy) < 1e-8 * np.max(np.abs(results["kinetic"]))
    assert np.ptp(h) < 1e-8 * np.max(np.abs(h))
    # the sections' rotation matters: without it (rho_I = 0, same equations) the motion differs
    plain = hub_beam(6.0, "rI", tip=True)
    plain.parameters["rI"] = 0.0
    plain.initial.update(model.initial)
    other = flexkane.simulate(compiled, t_end=2.0, dt_out=0.01, rtol=1e-11, atol=1e-13, model=plain)
    assert np.max(np.abs(other["q_B_1"] - results["q_B_1"])) > 1e-3


def test_rotary_inertia_is_read_from_and_written_to_model_files():
    from flexkane.model.toml_io import dumps_model, loads_model

    text = dumps_model(cantilever(2, "rI"))
    assert 'rotary_inertia = "rI"' in text
    assert loads_model(text).beams["B"].rotary_inertia == "rI"
    assert "rotary_inertia" not in dumps_model(cantilever(2, None))


@pytest.mark.parametrize("value, expected", [(-0.1, "non-negative"), ("rX", "rX")])
def test_invalid_rotary_inertia_is_refused_naming_the_field(value, expected):
    with pytest.raises(ModelError) as info:
        cantilever(2, value).validate()
    assert "beams.B.rotary_inertia" in str(info.value)
    assert expected in str(info.value)


def test_report_defines_the_rotary_constants_and_the_sections_angular_velocity():
    from flexkane.kane.numeric import constant_values
    from flexkane.report import constant_rows, equations_markdown

    eom = flexkane.derive(hub_beam(6.0, "rI"), cache=False)
    values = constant_values(eom)
    rows = {row[0]: row for row in constant_rows(eom, values)}
    ir = next(row for symbol, row in rows.items() if "Ir" in symbol)
    assert ir[2] == r"\int_0^L \rho I\,dx" and ir[3] == "kg m^2" and float(ir[4]) == pytest.approx(0.02)
    gr = next(row for symbol, row in rows.items() if "Gr" in symbol and "11" in symbol)
    assert gr[2] == r"\int_0^L \rho I\,\Phi_{1}'(x)\,\Phi_{1}'(x)\,dx" and gr[3] == "kg"
    assert "angular velocity of the section at x" in equations_markdown(eom, values)


def test_check_command_reads_rotary_inertia_and_refuses_a_negative_one(tmp_path, capsys):
    from flexkane.cli import main
    from flexkane.model.toml_io import dumps_model

    good = tmp_path / "rayleigh.toml"
    good.write_text(dumps_model(hub_beam(6.0, "rI")))
    assert main(["check", str(good)]) == 0
    assert "B: 3 clamped-free, Rayleigh" in capsys.readouterr().out
    bad = tmp_path / "negative.toml"
    bad.write_text(dumps_model(hub_beam(6.0, "-rI")))
    assert main(["check", str(bad)]) == 2
    err = capsys.readouterr().err
    assert "beams.B.rotary_inertia" in err and "non-negative" in err and "kg m" in err


@pytest.mark.slow
def test_driven_two_link_arm_with_rayleigh_beams_balances_power():
    """Joint torques' work equals the change of kinetic (sections' rotation included) plus strain
    energy; one beam with geometric stiffening, both with rotary inertia (labelled constants)."""
    model = flexkane.builtin_model("two-link-flexible-arm")
    model.beams["upper"].rotary_inertia = 0.002
    model.beams["upper"].geometric_stiffening = True
    model.beams["fore"].rotary_inertia = "0.001"
    model.validate()
    eom = flexkane.derive(model)
    assert {"Er_upper_1", "Gr_fore_12", "Ir_upper"} <= {s.name for s in eom.constants}
    results = flexkane.simulate(flexkane.compile_model(eom), rtol=1e-10, atol=1e-12)
    assert not results.partial
    scale = np.max(np.abs(results["work"])) + np.max(np.abs(results["kinetic"]))
    assert np.max(np.abs(results["energy_balance"])) < 1e-8 * scale
    assert np.max(np.abs(results["work"])) > 1e-3 * scale
