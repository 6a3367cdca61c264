"""A run that starts from the static equilibrium (``[initial] equilibrium = true``, ``--from-equilibrium``).

Oracles: the Euler-Bernoulli cantilever, ``F L^3 / (3 EI)`` at the tip under a tip load and
``q L^4 / (8 EI)`` under its own weight ``q = rho g``, and the Ritz solution with n clamped-free
modes in closed form (the modes' roots from ``cos b cosh b = -1`` found here, their tip values and
integrals from the closed-form shapes), to which the model must agree and which converges to the
beam's solution as n grows; a hanging pendulum is straight and vertical.
"""

import numpy as np
import pytest
from scipy.optimize import brentq

import flexkane
from flexkane.analysis.equilibrium_start import equilibrium_start
from flexkane.cli import main
from flexkane.derivation_cache import Derivation, structure_signature
from flexkane.errors import ModelError
from flexkane.model import dumps_model, loads_model
from flexkane.start_state import start_state

CANTILEVER = """
name = "cantilever"
[parameters]
L = 1.2
EI = 50.0
rho = 1.5
F = 0.01
[beams.B]
static_corrections = false   # the oracle is the Ritz solution in the clamped-free modes
L = "L"
EI = "EI"
rho = "rho"
n_modes = 4
[joints.base]
type = "weld"
parent = "ground"
child = "B"
[loads.tip]
body = "B"
station = "L"
force = [0, "-F"]
[initial]
equilibrium = true
[simulation]
t_end = 0.3
dt_out = 0.005
"""

#: The same beam under its own weight only (the tip load removed, gravity along -y).
HEAVY = CANTILEVER.replace('F = 0.01', 'g = 0.0981').replace('force = [0, "-F"]', 'force = [0, 0]') \
    + '[gravity]\ng = "g"\ndirection = [0, -1]\n'


def clamped_free_modes(n):
    """Roots b_i of cos b cosh b = -1 and, of the modes phi = cosh b x - cos b x - s (sinh b x - sin b x)
    (x = s/L, unit mean square), the tip values phi_i(1) and the integrals of phi_i over [0, 1]."""
    roots = np.array([brentq(lambda b: np.cos(b) * np.cosh(b) + 1, (i + 0.5) * np.pi - 1.0, (i + 0.5) * np.pi + 1.0)
                      for i in range(n)])
    s = (np.sinh(roots) - np.sin(roots)) / (np.cosh(roots) + np.cos(roots))
    tip = np.cosh(roots) - np.cos(roots) - s * (np.sinh(roots) - np.sin(roots))
    return roots, tip, 2 * s / roots


def tip_deflection(found, n):
    """w(L) of the beam B of an equilibrium found (the model's own shape functions at the tip)."""
    from flexkane.modes import get_family

    q = np.array([found.state[found.state_names.index(f"q_B_{i + 1}")] for i in range(n)])
    return float(get_family("clamped-free").phi(np.array([1.0]), n)[:, 0] @ q)


def test_tip_load_deflection_is_the_ritz_solution_and_converges_to_F_L3_over_3EI():
    model = loads_model(CANTILEVER)
    F, L, EI = (model.parameters[k] for k in ("F", "L", "EI"))
    beam = -F * L ** 3 / (3 * EI)
    errors = []
    for n in range(1, 5):
        found = equilibrium_start(model.with_modes(n))
        roots, tip, _ = clamped_free_modes(n)
        ritz = -F * L ** 3 / EI * np.sum(tip ** 2 / roots ** 4)     # q_i = F phi_i(1) L^3 / (EI b_i^4)
        assert tip_deflection(found, n) == pytest.approx(ritz, rel=1e-10)   # measured 1.6e-13 (bent by 1e-4 L)
        assert found.relative_residual < 1e-12
        errors.append(abs(tip_deflection(found, n) - beam) / abs(beam))
    # measured: 2.9e-2, 4.6e-3, 1.4e-3, 6.2e-4 (the modal series' tail falls as n^-3)
    assert all(later < 0.7 * earlier for earlier, later in zip(errors, errors[1:]))
    assert errors[0] > 0.02 and errors[-1] < 1e-3


def test_weight_deflection_is_the_ritz_solution_and_converges_to_q_L4_over_8EI():
    model = loads_model(HEAVY)
    g, rho, L, EI = (model.parameters[k] for k in ("g", "rho", "L", "EI"))
    beam = -rho * g * L ** 4 / (8 * EI)
    errors = []
    for n in range(1, 5):
        found = equilibrium_start(model.with_modes(n))
        roots, tip, integral = clamped_free_modes(n)
        ritz = -rho * g * L ** 4 / EI * np.sum(tip * integral / roots ** 4)  # q_i = -rho g L^4 int(phi_i) / (EI b_i^4)
        assert tip_deflection(found, n) == pytest.approx(ritz, rel=1e-10)
        errors.append(abs(tip_deflection(found, n) - beam) / abs(beam))
    # measured: 1.3e-2, 9.1e-4, 1.6e-4, 4.2e-5 (alternating in sign)
    assert all(later < 0.5 * earlier for earlier, later in zip(errors, errors[1:]))
    assert errors[-1] < 1e-4


def test_a_run_from_the_equilibrium_stays_at_rest():
    model = loads_model(CANTILEVER)
    compiled = flexkane.compile_model(flexkane.derive(model))
    still = flexkane.simulate(compiled, model=model, rtol=1e-10, atol=1e-14)
    undeformed = flexkane.simulate(compiled, model=model.with_values({"initial.equilibrium": False}),
                                   rtol=1e-10, atol=1e-14)
    names = [f"q_B_{i}" for i in range(1, 5)]
    q0 = np.array([still[name][0] for name in names])
    moved = max(np.max(np.abs(still[name] - q)) for name, q in zip(names, q0))
    rang = max(np.max(np.abs(undeformed[name])) for name in names)
    assert np.max(np.abs(q0)) > 1e-6 and undeformed["q_B_1"][0] == 0.0
    assert rang > 0.5 * np.max(np.abs(q0))           # released undeformed, it rings about q0
    assert moved < 1e-10 * rang, (moved, rang)      # measured 5e-16 m against 1.1e-4 m
    assert still.solver["equilibrium"]["relative_residual"] < 1e-12


@pytest.mark.parametrize("pivot, upright", [(0.5, False), (1.2, True)])
def test_a_pendulum_without_driver_hangs_straight_and_an_upright_end_is_called_unstable(pivot, upright):
    """pendulum-beam (angle 0: the rod along -y): from 0.5 rad with its rod bent the search ends hanging,
    from 1.2 rad upright (measured), which the start reports as unstable (one growing eigenvalue)."""
    model = flexkane.builtin_model("pendulum-beam").with_values(
        {"initial.equilibrium": True, "initial.q_pivot": pivot, "initial.q_rod_1": 0.01})
    found = equilibrium_start(model)
    state = dict(zip(found.state_names, found.state))
    assert found.unknowns == ["q_pivot", "q_rod_1", "q_rod_2", "q_rod_3"]
    assert found.iterations > 0
    assert state["q_pivot"] == pytest.approx(np.pi if upright else 0.0, abs=1e-10)
    for name in ("q_rod_1", "q_rod_2", "q_rod_3"):      # straight, along the vertical
        assert abs(state[name]) < 1e-10, (name, state[name])
    assert found.unstable == (1 if upright else 0)


def test_a_free_body_under_gravity_is_refused_naming_the_key_and_the_remedy():
    model = flexkane.builtin_model("falling-beam").with_values({"initial.equilibrium": True})
    with pytest.raises(ModelError) as info:
        equilibrium_start(model)
    message = str(info.value)
    assert info.value.path == "initial.equilibrium"
    assert "free fall" in message and "initial.equilibrium = false" in message and "--set g=0" in message
    assert "--about" not in message                  # linearize's options are not this command's


def test_a_speed_given_with_the_equilibrium_start_is_refused():
    model = flexkane.builtin_model("pendulum-beam").with_values({"initial.equilibrium": True, "u_pivot": 0.5})
    with pytest.raises(ModelError, match=r"initial\.u_pivot: expected 0 or no value"):
        equilibrium_start(model)


def test_the_key_is_true_or_false_and_survives_a_round_trip_through_toml():
    model = loads_model(CANTILEVER)
    back = loads_model(dumps_model(model))
    assert back.initial == {"equilibrium": True} and dumps_model(back) == dumps_model(model)
    with pytest.raises(ModelError, match=r"initial\.equilibrium: expected true or false"):
        model.with_values({"initial.equilibrium": 1})
    assert model.with_modes(2).initial == {"equilibrium": True}


def test_the_flag_shares_the_equations_but_not_the_numbers_and_a_repeat_reads_the_cache(monkeypatch):
    at_rest = loads_model(CANTILEVER).with_modes(2)
    released = at_rest.with_values({"initial.equilibrium": False})
    assert structure_signature(at_rest) == structure_signature(released)
    derivation = Derivation(at_rest)
    assert derivation._numbers_path(at_rest) != derivation._numbers_path(released)
    first = start_state(derivation, at_rest, remember=True)
    assert np.all(start_state(Derivation(released), released).state == 0.0)

    def no_search(*args, **kwargs):
        raise AssertionError("searched again")

    monkeypatch.setattr("flexkane.analysis.equilibrium_start.equilibrium_start", no_search)
    again = start_state(Derivation(at_rest), at_rest)
    assert np.array_equal(again.state, first.state) and again.equilibrium == first.equilibrium
    assert np.any(first.state != 0.0)


def test_run_from_equilibrium_flag_starts_there_and_a_free_body_exits_2(tmp_path, capsys):
    path = tmp_path / "cantilever.toml"
    path.write_text(CANTILEVER.replace("equilibrium = true", "equilibrium = false"))
    code = main(["run", str(path), "--from-equilibrium", "--no-plots", "--out", str(tmp_path / "run")])
    out = capsys.readouterr().out
    assert code == 0 and "static equilibrium" in out
    assert loads_model((tmp_path / "run" / "model.toml").read_text()).initial["equilibrium"] is True
    results = flexkane.load_results(tmp_path / "run" / "results.npz")
    assert results["q_B_1"][0] != 0.0 and np.ptp(results["q_B_1"]) < 1e-8 * abs(results["q_B_1"][0])
    code = main(["run", "falling-beam", "--from-equilibrium", "--no-plots", "--out", str(tmp_path / "fall")])
    err = capsys.readouterr().err
    assert code == 2 and "initial.equilibrium" in err and "Traceback" not in err


def test_a_run_from_an_unstable_equilibrium_warns():
    model = flexkane.builtin_model("pendulum-beam").with_values(
        {"initial.equilibrium": True, "initial.q_pivot": 1.2, "initial.q_rod_1": 0.01})
    results = flexkane.simulate(flexkane.compile_model(flexkane.derive(model)), model=model, t_end=0.01, dt_out=0.01)
    assert results["q_pivot"][0] == pytest.approx(np.pi, abs=1e-10) and results.solver["equilibrium"]["unstable"] == 1
    assert any("unstable" in w and "[initial]" in w for w in results.warnings)
