"""A run that cannot reach its end time stops with a message naming the time reached and the likely
cause, writes what it computed (marked partial) and exits with code 3.

The model is a pendulum driven by the torque T0/(t1 - t): the speed grows like -log(1 - t/t1) and the
solution has no continuation past t1 = 1 s. With the pin at the mass centre and no moment of inertia
(valid values, each non-negative) the mass matrix is singular from the start.
"""

import csv

import numpy as np

import flexkane
from flexkane.cli import main


def _rows(path):
    with open(path, newline="") as handle:
        lines = [line for line in handle if not line.startswith("#")]
    return list(csv.reader(lines))


def test_simulate_returns_partial_results_up_to_the_blow_up(torque_pendulum):
    model, compiled = torque_pendulum
    results = flexkane.simulate(compiled, t_end=2.0, dt_out=0.01)
    assert results.partial
    assert results.solver["status"] == "step_too_small"
    assert 0.98 <= results.solver["t_reached"] <= 1.0
    assert 0.97 <= results.t[-1] <= results.solver["t_reached"]
    assert np.all(np.isfinite(results.state))
    assert results["energy"][-1] > 3 * results["energy"][0]   # the torque pumps energy in without bound
    assert "t = 1 s" in results.solver["message"] and "singular" in results.solver["message"]


def test_run_of_a_divergent_model_exits_3_and_writes_partial_results(torque_pendulum, torque_pendulum_file,
                                                                      tmp_path, capsys):
    out = tmp_path / "diverged"
    assert main(["run", str(torque_pendulum_file), "--out", str(out), "--quiet"]) == 3
    err = capsys.readouterr().err
    assert "Traceback" not in err
    failure = [line for line in err.splitlines() if line.startswith("flexkane: solver failure:")]
    assert len(failure) == 1
    assert "stopped at t = 1 s" in failure[0] and "step size too small" in failure[0]
    assert "blow-up" in failure[0] and f"partial results written to {out}" in failure[0]
    rows = _rows(out / "results.csv")
    assert rows[0][:3] == ["t", "q_pin", "u_pin"]
    assert 0.97 <= float(rows[-1][0]) < 1.0 and len(rows) == 1 + round(float(rows[-1][0]) / 0.01) + 1
    assert (out / "results.csv").read_text().splitlines()[-1].startswith("# partial: step size too small")
    saved = flexkane.load_results(out)
    assert saved.partial and saved.solver["status"] == "step_too_small"
    np.testing.assert_array_equal(saved.t, [float(r[0]) for r in rows[1:]])
    assert (out / "model.toml").exists() and (out / "equations.md").exists()


def test_a_singular_mass_matrix_from_valid_values_exits_3_at_t_0(torque_pendulum, torque_pendulum_file,
                                                                 tmp_path, capsys):
    out = tmp_path / "singular"
    out.mkdir()
    (out / "notes.txt").write_text("kept")
    code = main(["run", str(torque_pendulum_file), "--set", "a=0", "--set", "J=0", "--out", str(out),
                 "--quiet", "--force"])
    err = capsys.readouterr().err
    assert code == 3 and "Traceback" not in err
    assert "stopped at t = 0 s" in err and "singular mass matrix" in err and "check the parameters" in err
    saved = flexkane.load_results(out)
    assert saved.partial and saved.solver["status"] == "singular_mass_matrix"
    assert len(saved.t) <= 1
    assert (out / "notes.txt").read_text() == "kept"    # --force keeps the directory's other files

