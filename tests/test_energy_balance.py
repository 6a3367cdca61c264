"""The energy balance a run prints is a real check: it falls with the tolerance.

The work ``W`` of drivers, loads, actuator torques and dampers is integrated with the motion, so
``E - E0 - W`` is the integration error alone. Two small chains through ``flexkane run``: a torque
switched off at t = 0.5 s (a step), and a shoulder driven along a prescribed angle (the driver's
effort does work) with a damped elbow spring under gravity.
"""

from __future__ import annotations

import re

import numpy as np
import pytest

import flexkane
from flexkane.cli import main

TWO_LINKS = """
name = "{name}"

[bodies.arm]
mass = 1.0
inertia = 0.1
points = {{ elbow = [0.5, 0] }}

[bodies.hand]
mass = 0.5
inertia = 0.02
points = {{ pin = [-0.3, 0] }}

[joints.shoulder]
type = "revolute"
parent = "ground"
child = "arm"
{shoulder}

[joints.elbow]
type = "revolute"
parent = "arm"
parent_point = "elbow"
child = "hand"
child_point = "pin"
stiffness = 5.0
{elbow}

[simulation]
t_end = 1.5
dt_out = 0.01
"""

MODELS = {
    "step-torque": TWO_LINKS.format(name="step-torque", shoulder='torque = "where(t < 0.5, 2.0, 0)"',
                                    elbow=""),
    "driven-damped": TWO_LINKS.format(name="driven-damped",
                                      shoulder='driver = { coordinate = "0.8*sin(3*t)" }',
                                      elbow="damping = 0.3\n\n[gravity]\ng = 9.81\ndirection = [0, -1]"
                                            "\n\n[initial]\nq_elbow = 0.4"),
}


def _printed_balance(capsys, model, out, rtol) -> float:
    assert main(["run", str(model), "--out", str(out), "--rtol", str(rtol), "--atol", "1e-12"]) == 0
    text = capsys.readouterr().out
    match = re.search(r"energy balance E - E0 - W (\S+) \(relative", text)
    assert match, text
    return float(match.group(1))


@pytest.mark.slow
@pytest.mark.parametrize("name", sorted(MODELS))
def test_printed_balance_falls_with_the_tolerance(tmp_path, capsys, name):
    model = tmp_path / f"{name}.toml"
    model.write_text(MODELS[name])
    loose = _printed_balance(capsys, model, tmp_path / "loose", 1e-6)
    tight = _printed_balance(capsys, model, tmp_path / "tight", 1e-10)
    assert tight < 1e-9
    assert loose > 100 * tight
    res = flexkane.load_results(tmp_path / "tight")
    assert np.any(res["work"] != 0)
    np.testing.assert_allclose(res["energy_balance"], res["energy"] - res["energy"][0] - res["work"],
                               rtol=0, atol=1e-15 * np.abs(res["energy"]).max())
    assert (tmp_path / "tight" / "energy.png").stat().st_size > 5000


@pytest.mark.slow
def test_a_torque_with_a_huge_integer_coefficient_runs(tmp_path, capsys):
    """``(3*t)**50`` = 3**50 t**50 (3**50 > 2**63): generated as a float, it compiles and runs."""
    model = tmp_path / "power-torque.toml"
    model.write_text(TWO_LINKS.format(name="power-torque", shoulder='torque = "(3*t)**50"', elbow="")
                     .replace("t_end = 1.5", "t_end = 0.3"))
    assert main(["run", str(model), "--out", str(tmp_path / "out"), "--quiet"]) == 0
    res = flexkane.load_results(tmp_path / "out")
    assert np.all(np.isfinite(res.state)) and res["u_shoulder"][-1] > 0
