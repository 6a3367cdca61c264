"""Controllers in the loop of spatial models: simulate(..., controller=f), and the standalone C of a
spatial model with controller states.

Physics is the oracle: an attitude law T = -Kp e_vec - Kd w (Euler parameters, body axes) brings a
tumbling free body to rest, whether written in the model file or computed by a Python (or Numba)
function from the state, and the actuator's power is the rate of kinetic energy (the energy balance
stays at the solver's error); a PD law on a skew revolute joint integrates as its spring and damper.
The compiled runs are slow (new structures compile in 10-20 s); the default run checks the same facts
on the equations evaluated without compiling (tests/kane/test_spatial_state_feedback.py,
tests/analysis/test_spatial_control_linearization.py) and the exported C against them here.
"""

from __future__ import annotations

import numpy as np
import pytest
from numba import njit
from spatial_control_models import (ATTITUDE_LAW, ATTITUDE_PI, INTEGRAL, KD_ATT, KP_ATT, NO_TORQUE, PD_LAW, PID,
                                    SPRING, Evaluated, attitude, hinge, random_states)
from test_c_export import _call, _close, _compare_at_random_states, _compile, _Numba, needs_cc

import flexkane
from flexkane.c_export import c_constants, export_c
from flexkane.numerics.c_source import c_identifier

RUN = dict(t_end=30.0, dt_out=0.5, rtol=1e-11, atol=1e-13, method="dop853")
#: A large attitude error and a tumble (and a drift, which the law leaves alone).
TUMBLE = {"q_float": {"axis": [1.0, 2.0, -1.0], "angle": 2.5}, "u_float_wx": 0.3, "u_float_wy": -0.2,
          "u_float_wz": 0.5, "u_float_vx": 0.1}


def attitude_law(t, y):
    """T = -Kp e_vec - Kd w from y = [x, y, z, e0, e1, e2, e3, vx, vy, vz, wx, wy, wz]."""
    return -KP_ATT * np.asarray(y[4:7]) - KD_ATT * np.asarray(y[10:13])


@njit
def attitude_law_compiled(t, y):
    return -KP_ATT * y[4:7] - KD_ATT * y[10:13]


@pytest.mark.slow
def test_attitude_controller_brings_a_tumbling_body_to_rest_in_the_file_and_in_python():
    law = flexkane.simulate(flexkane.compile_model(flexkane.derive(attitude(ATTITUDE_LAW).with_values(TUMBLE))),
                            **RUN)
    free = flexkane.compile_model(flexkane.derive(attitude(NO_TORQUE).with_values(TUMBLE)))
    python = flexkane.simulate(free, controller=attitude_law, **RUN)
    assert python.state_names == law.state_names
    np.testing.assert_allclose(python.state, law.state, rtol=0, atol=1e-10)
    np.testing.assert_allclose(python["input_load_attitude_tx"], law["load_attitude_tx"], rtol=0, atol=1e-10)
    compiled = flexkane.simulate(free, controller=attitude_law_compiled, **RUN)
    np.testing.assert_array_equal(compiled.state, python.state)
    final = dict(zip(law.state_names, law.state[-1]))
    assert abs(abs(final["q_float_e0"]) - 1) < 1e-8            # the attitude error is gone
    assert max(abs(final[f"u_float_w{c}"]) for c in "xyz") < 1e-3   # slowest mode: exp(-Kd t / (2 I_3))
    assert max(abs(final[f"q_float_e{k}"]) for k in (1, 2, 3)) < 1e-3
    energy = law["kinetic"]
    assert np.abs(law["energy_balance"]).max() < 1e-9 * energy.max()  # actuator power = rate of energy
    assert np.ptp(law["work"]) > 0.5 * energy[0]                         # the law removed the tumble


@pytest.mark.slow
def test_pd_law_on_a_spatial_revolute_joint_integrates_as_its_spring():
    run = dict(t_end=2.0, dt_out=0.05, rtol=1e-12, atol=1e-14, method="dop853")
    law = flexkane.simulate(flexkane.compile_model(flexkane.derive(hinge(PD_LAW))), **run)
    spring = flexkane.simulate(flexkane.compile_model(flexkane.derive(hinge(SPRING))), **run)
    np.testing.assert_allclose(law.state, spring.state, rtol=0, atol=1e-10)
    # the law's torque does the work the spring's energy stores: both balances hold to solver error
    for run_ in (law, spring):
        assert np.abs(run_["energy_balance"]).max() < 1e-9 * np.abs(run_["energy"]).max()
    assert np.ptp(law["work"]) > 1e-2 * np.abs(law["energy"]).max()


@pytest.fixture(scope="module")
def exported(tmp_path_factory):
    """Model -> (model, the loaded C library, prefix, directory), exported once."""
    cache = {}

    def get(name):
        if name not in cache:
            model = {"pid-hinge": lambda: hinge(PID), "attitude-pi": lambda: attitude(ATTITUDE_PI, INTEGRAL)}[name]()
            directory = tmp_path_factory.mktemp(name)
            export_c(model, directory, force=True)
            prefix = c_identifier(model.name)
            cache[name] = (model, _compile(directory, prefix), prefix, directory)
        return cache[name]
    return get


#: The models exported: a PID with saturation and a filtered sensor; an attitude PI with Euler
#: parameters (more q than u) and three integral states; (nq, nu, nz) of each.
EXPORTED = [("pid-hinge", (1, 1, 2)), ("attitude-pi", (7, 6, 3))]


@needs_cc
@pytest.mark.parametrize("name, counts", EXPORTED)
def test_c_of_a_spatial_model_with_controller_states_computes_its_equations(exported, name, counts):
    """rhs (q', u', z'), controller rates and outputs of the C at random states (some saturated)
    equal the equations; the header counts q, u and z apart."""
    model, lib, prefix, directory = exported(name)
    eom = flexkane.derive(model)
    assert (len(eom.q), len(eom.u), len(eom.z)) == counts
    nq, nu, nz = counts
    equations = Evaluated(eom)
    p = np.array([c.value for c in c_constants(eom, model)[0]])   # the C's parameters
    ny = nq + nu + nz
    names = list(eom.compact.outputs)
    states = random_states(eom, 3)
    if name == "pid-hinge":    # beyond both saturation limits
        states += [np.array([-9.0, 0.0, 0.0, 0.0]), np.array([9.0, 0.0, 0.0, 0.0])]
    for y in states:
        status, dy = _call(getattr(lib, f"{prefix}_rhs"), 0.2, y, p, ny)
        assert status == 0
        _close(dy, equations.rhs(0.2, y))
        status, rates = _call(getattr(lib, f"{prefix}_controller_rates"), 0.2, y, p, nz)
        assert status == 0
        np.testing.assert_array_equal(rates, dy[nq + nu:])
        status, out = _call(getattr(lib, f"{prefix}_outputs"), 0.2, y, p, len(names))
        assert status == 0
        expected = equations.outputs(0.2, y)
        _close(out, [expected[k] for k in names], rtol=1e-11)
    header = (directory / f"{prefix}.h").read_text()
    for key, count in zip(("NQ", "NU", "NZ"), counts):
        assert f"#define {prefix.upper()}_{key} {count}" in header


@needs_cc
@pytest.mark.slow
@pytest.mark.parametrize("name", [name for name, _ in EXPORTED])
def test_c_of_a_spatial_model_with_controller_states_matches_numba(exported, name):
    model, lib, prefix, _ = exported(name)
    _compare_at_random_states(model, _Numba(model), lib, prefix)
