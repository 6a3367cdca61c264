"""The linearize, campbell and converge commands: files, tables, exit codes; the matrix export."""

import csv

import numpy as np
import pytest
import scipy.io

import flexkane
from flexkane import Model
from flexkane.cli import main
from flexkane.analysis import linearize, modal_analysis
from flexkane.model.parts import Beam, Joint


def read_csv(path):
    with open(path, newline="") as handle:
        return list(csv.reader(handle))


def test_linearize_writes_matrices_modes_and_mode_shapes(tmp_path, capsys):
    out = tmp_path / "arm"
    assert main(["linearize", "flexible-arm", "--n-modes", "2", "--out", str(out)]) == 0
    printed = capsys.readouterr().out
    assert "1 rigid-body mode" in printed and "omega_n [rad/s]" in printed and "f_n [Hz]" in printed
    assert sorted(p.name for p in out.iterdir()) == ["linear_model.mat", "linear_model.npz", "mode_shapes.png",
                                                     "modes.csv"]
    rows = read_csv(out / "modes.csv")
    assert rows[0][:3] == ["mode", "kind", "omega_n [rad/s]"]
    assert [r[1] for r in rows[1:]] == ["rigid", "oscillatory", "oscillatory"]
    assert (out / "mode_shapes.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_free_floating_chain_is_linearized_about_rest_from_the_command_line(tmp_path, capsys):
    code = main(["linearize", "falling-beam-exact", "--set", "g=0", "--about", "rest", "--out", str(tmp_path / "f")])
    assert code == 0
    assert "3 rigid-body modes" in capsys.readouterr().out


def test_model_without_equilibrium_exits_2_and_says_so(tmp_path, capsys):
    assert main(["linearize", "falling-beam-exact", "--out", str(tmp_path / "f")]) == 2
    err = capsys.readouterr().err
    assert "has no equilibrium" in err and "Traceback" not in err
    assert not (tmp_path / "f").exists()


def test_exported_matrices_load_in_numpy_and_matlab_format(tmp_path):
    linear = linearize(flexkane.builtin_model("flexible-arm").with_modes(2))
    linear.save_npz(tmp_path / "m.npz")
    linear.save_mat(tmp_path / "m.mat")
    A, B = linear.state_space()
    with np.load(tmp_path / "m.npz") as data:                 # no pickled objects
        np.testing.assert_array_equal(data["A"], A)
        np.testing.assert_array_equal(data["B_ss"], B)
        np.testing.assert_array_equal(data["K"], linear.K)
        assert list(data["state_names"]) == linear.state_names
        assert list(data["input_names"]) == ["input_effort_shoulder"]
    mat = scipy.io.loadmat(tmp_path / "m.mat")
    np.testing.assert_array_equal(mat["A"], A)
    np.testing.assert_array_equal(mat["M"], linear.M)
    assert [str(c[0][0]) for c in mat["state_names"]] == linear.state_names
    # a torque input on the hub only moves the speeds
    assert np.all(B[:linear.n] == 0) and np.abs(B[linear.n:]).max() > 0


def test_model_without_inputs_has_input_matrix_with_zero_columns(tmp_path):
    linear = linearize(flexkane.builtin_model("spin-up-linear"), about="spin", spin=1.0)
    A, B = linear.state_space()
    assert B.shape == (2 * linear.n, 0) and linear.B.shape == (linear.n, 0)
    linear.save_mat(tmp_path / "s.mat")
    assert scipy.io.loadmat(tmp_path / "s.mat")["B_ss"].size == 0


def test_second_order_form_of_a_free_joint_uses_the_kinematic_equations():
    model = flexkane.builtin_model("falling-beam-exact")
    model.parameters["g"] = 0
    linear = linearize(model, about="rest")                    # q3 = 1: u1, u2 are along the body axes
    c, s = np.cos(1.0), np.sin(1.0)
    np.testing.assert_allclose(linear.W[:2, :2], [[c, -s], [s, c]], atol=1e-15)
    Mq, Cq, Kq, Bq = linear.second_order()
    np.testing.assert_allclose(linear.W.T @ Mq @ linear.W, linear.M, atol=1e-14)
    np.testing.assert_allclose(Mq, Mq.T, atol=1e-14)
    np.testing.assert_allclose(Kq, linear.K, atol=1e-12)      # only the elastic coordinate is stiff
    # the same frequencies in both forms
    omega = np.sqrt(np.sort(np.linalg.eigvals(np.linalg.solve(Mq, Kq)).real)[-1])
    assert omega == pytest.approx(modal_analysis(linear).frequencies[0], rel=1e-10)


def test_campbell_writes_csv_and_png_and_marks_divergence(tmp_path, capsys):
    out = tmp_path / "c"
    assert main(["campbell", "spin-up-linear", "--n-modes", "2", "--spin", "0:6:4", "--out", str(out)]) == 0
    assert "unstable" in capsys.readouterr().out
    rows = read_csv(out / "campbell.csv")
    assert rows[0] == ["Omega [rad/s]", "omega_1 [rad/s]", "omega_2 [rad/s]", "max_growth_rate [1/s]"]
    assert [float(r[0]) for r in rows[1:]] == [0.0, 2.0, 4.0, 6.0]
    assert float(rows[-1][1]) == 0.0 and float(rows[-1][-1]) > 0          # diverged at 6 rad/s
    assert (out / "campbell.png").stat().st_size > 1000


@pytest.mark.parametrize("spin", ["0:8", "a:b:c", "0:8:0", ""])
def test_campbell_rejects_malformed_spin_ranges(tmp_path, capsys, spin):
    assert main(["campbell", "spin-up", "--spin", spin, "--out", str(tmp_path / "c")]) == 2
    assert "--spin" in capsys.readouterr().err


def test_converge_tabulates_frequencies_as_modes_are_added(tmp_path, capsys):
    out = tmp_path / "v"
    assert main(["converge", "flexible-arm", "--n-modes", "1..3", "--out", str(out)]) == 0
    assert "change" in capsys.readouterr().out
    rows = read_csv(out / "convergence.csv")
    assert rows[0][:3] == ["n_modes", "omega_1 [rad/s]", "omega_2 [rad/s]"]
    first = [float(r[1]) for r in rows[1:]]
    assert first[0] > first[1] > first[2]                     # Rayleigh-Ritz: from above


def test_converge_follows_an_output_at_a_time(tmp_path, capsys):
    # the cantilever of tests/modes/test_kane_matches_free_vibration.py (its compiled module is reused)
    model = Model(name="cantilever", parameters={"L": 1.2, "EI": 20.0, "rho": 0.8})
    model.beams["B"] = Beam(name="B", L="L", EI="EI", rho="rho", n_modes=4)
    model.joints["clamp"] = Joint(name="clamp", type="weld", parent="ground", child="B")
    model.initial["q_B_1"] = 0.01
    path = tmp_path / "cantilever.toml"
    flexkane.save_model(model, path)
    out = tmp_path / "v"
    assert main(["converge", str(path), "--n-modes", "4", "--output", "tip_B", "--at", "0.05",
                 "--out", str(out)]) == 0
    rows = read_csv(out / "convergence.csv")
    assert rows[0][-1] == "tip_B(t=0.05 s)"
    p1 = float(rows[1][1])
    phi_tip = flexkane.derive(model).constant_values()
    tip = {s.name: v for s, v in phi_tip.items()}["Phi_1(L)"]
    assert float(rows[1][-1]) == pytest.approx(0.01 * tip * np.cos(p1 * 0.05), rel=1e-7)


def test_converge_needs_output_and_time_together(tmp_path, capsys):
    assert main(["converge", "flexible-arm", "--n-modes", "1..2", "--output", "tip_link",
                 "--out", str(tmp_path / "v")]) == 2
    assert "--at" in capsys.readouterr().err
