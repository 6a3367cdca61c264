"""Every built-in example runs from the command line and from Python, with the standard outputs."""

import csv

import numpy as np
import pytest

import flexkane
from flexkane.builtin import builtin_names
from flexkane.cli import main


#: Built-ins whose run from the command line costs a compile of 15 to 25 s on CI: run in the slow set
#: (their physics, in tests/test_spatial_flexible_examples_physics.py, runs them in the default set).
SLOW_TO_COMPILE = {"robot-arm-3d-flexible", "spacecraft-flexible-slew"}


@pytest.mark.parametrize("name", [pytest.param(n, marks=pytest.mark.slow) if n in SLOW_TO_COMPILE else n
                                  for n in builtin_names()])
def test_example_runs_from_the_command_line(name, tmp_path):
    model = flexkane.builtin_model(name)
    t_end = min(model.simulation.t_end, 0.02)
    out = tmp_path / name
    assert main(["run", name, "--out", str(out), "--quiet", "--t-end", str(t_end), "--dt-out", str(t_end / 4)]) == 0
    rows = list(csv.reader(open(out / "results.csv")))
    assert rows[0][0] == "t" and len(rows) == 6
    assert all(np.isfinite(float(v)) for v in rows[-1])
    for beam in model.beams:     # a spatial beam's tip deflects along both principal axes
        assert all(c in rows[0] for c in ([f"tip_{beam}_y", f"tip_{beam}_z"] if model.dimensions == 3
                                          else [f"tip_{beam}"]))
    assert (out / "equations.md").stat().st_size > 1000
    assert (out / "energy.png").exists()


def test_example_runs_from_python():
    model = flexkane.builtin_model("two-link-flexible-arm")
    results = flexkane.simulate(flexkane.compile_model(flexkane.derive(model)), t_end=0.05, dt_out=0.01,
                                rtol=1e-8, atol=1e-10)
    assert results.state_names[:2] == ["q_shoulder", "q_upper_1"]
    assert np.all(np.isfinite(results.state)) and results["q_shoulder"][-1] > 0
